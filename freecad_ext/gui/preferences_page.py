"""Edit > Preferences > Path (CAM) > IsoCAM: defaults for new operations.

One group per available operation row, one field per setup property, built
from the operation's SetupSheet prototype (its property types, tooltips and
built-in defaults), so a new row gets its defaults page without a .ui file.
Values are stored by freecad_ext.preferences.
"""

import FreeCADGui
from PySide import QtGui

from freecad_ext import compat, operations, preferences

log = compat.logger(__name__)


def _prototype(spec):
    """The SetupSheet prototype of the row's op (importing its module
    registers it)."""
    module = spec.import_module()
    name = getattr(module, "OP_NAME", spec.name)
    registered = compat.PathSetupSheet._RegisteredOps.get(name)
    if registered is None:
        return name, None, []
    return name, registered.prototype(name), list(module.SetupProperties())


QUANTITY_TYPES = ("App::PropertyLength", "App::PropertyDistance")
NUMBER_TYPES = ("App::PropertyInteger", "App::PropertyPercent", "App::PropertyFloat")


class _Field:
    """One setup property's editor on the page: a quantity (mm), a number,
    a choice, or text. Numbers are stored as floats, choices and text as
    strings (freecad_ext.preferences converts them back)."""

    def __init__(self, op_name, prop):
        self.op_name = op_name
        self.name = prop.name
        self.kind = "text"
        self.default = prop.getValue()
        if prop.propType in QUANTITY_TYPES:
            self.kind = "quantity"
            self.widget = FreeCADGui.UiLoader().createWidget("Gui::QuantitySpinBox")
            self.widget.setProperty("unit", "mm")
            self.widget.setProperty("minimum", 0.0)
            self.widget.setProperty("maximum", 1e6)
        elif prop.propType in NUMBER_TYPES:
            self.kind = "number"
            self.widget = QtGui.QDoubleSpinBox()
            self.widget.setRange(-1e9, 1e9)
            self.widget.setDecimals(0 if prop.propType != "App::PropertyFloat" else 4)
        elif prop.propType == "App::PropertyEnumeration":
            self.kind = "choice"
            self.widget = QtGui.QComboBox()
            self.widget.addItems([str(v) for v in prop.getEnumValues()])
        else:
            self.widget = QtGui.QLineEdit()
        self.widget.setObjectName("%s_%s" % (op_name, prop.name))
        self.widget.setToolTip(prop.info or "")

    def _builtin(self):
        value = self.default
        if self.kind in ("quantity", "number"):
            return float(getattr(value, "Value", value) or 0.0)
        return "" if value is None else str(value)

    def load(self, stored):
        value = stored.get(self.name, self._builtin())
        if self.kind == "quantity":
            self.widget.setProperty("rawValue", float(value))
        elif self.kind == "number":
            self.widget.setValue(float(value))
        elif self.kind == "choice":
            index = self.widget.findText(str(value))
            self.widget.setCurrentIndex(max(index, 0))
        else:
            self.widget.setText(str(value))

    def save(self):
        if self.kind == "quantity":
            value = float(self.widget.property("rawValue"))
        elif self.kind == "number":
            value = float(self.widget.value())
        elif self.kind == "choice":
            value = self.widget.currentText()
        else:
            value = self.widget.text()
        preferences.store_default(self.op_name, self.name, value)


class PreferencesPage:
    """FreeCAD preference page (``form``, ``loadSettings``, ``saveSettings``)."""

    def __init__(self, parent=None):
        self.form = QtGui.QWidget(parent)
        self.form.setWindowTitle("IsoCAM")
        layout = QtGui.QVBoxLayout(self.form)
        intro = QtGui.QLabel(
            "Defaults for new IsoCAM operations made from the toolbar or menu. "
            "A Job whose SetupSheet (or template) sets a value overrides them."
        )
        intro.setWordWrap(True)
        layout.addWidget(intro)
        self.fields = []
        for spec in operations.available():
            try:
                op_name, prototype, props = _prototype(spec)
            except Exception as exc:
                log.error("%s: %s" % (spec.module, exc))
                continue
            if prototype is None:
                continue
            box = QtGui.QGroupBox(spec.menu_text)
            form = QtGui.QFormLayout(box)
            for name in props:
                field = _Field(op_name, prototype.getProperty(name))
                form.addRow(name, field.widget)
                self.fields.append(field)
            layout.addWidget(box)
        layout.addStretch(1)

    def loadSettings(self):
        stored = {}
        for field in self.fields:
            if field.op_name not in stored:
                stored[field.op_name] = preferences.stored_defaults(field.op_name)
            field.load(stored[field.op_name])

    def saveSettings(self):
        for field in self.fields:
            field.save()
