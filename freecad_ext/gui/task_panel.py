"""Task panel of IsoCAM operations, the way FreeCAD's own operations have one.

FreeCAD's TaskPanel (compat.gui().OpGui.TaskPanel) brings the standard pages
the operation's features ask for -- Base Geometry, Depths (pocketing ops),
Heights -- and we add :class:`OperationPage`, built from the row's
Resources/panels/<name>.ui (or generated from the op's SetupProperties()).

Binding is by name: a widget whose objectName is a setup property edits that
property (Gui::QuantitySpinBox for lengths, with units and expressions; a
combo box for enumerations; check and spin boxes for the rest). Values are
checked as they are typed with the row's rules (freecad_ext.operations) and
the reasons shown in the page; the certificate the op writes after a run is
shown under them.

OK and Apply compute before the panel closes: if the user cancels the
computation (freecad_ext.gui.progress) the panel stays open, the operation
keeps its previous path and the message says so; Cancel then discards the
edit as usual.
"""

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from freecad_ext import compat, op_base, operations
from freecad_ext.compat import translate
from freecad_ext.gui import progress, qt_objects

log = compat.logger(__name__)

_base = compat.gui().OpGui

CERTIFICATE_GROUP = op_base.OUTPUT_GROUP  # read-only outputs the op writes
QUANTITY_TYPES = ("Length", "Distance", "Angle", "Speed", "Quantity", "Area")


# -- bindings: one widget <-> one property --------------------------------------


class QuantityBinding:
    """A Gui::QuantitySpinBox bound through FreeCAD's Path helper (units,
    expressions, only writes a changed value)."""

    def __init__(self, widget, obj, prop):
        self.widget = widget
        self.prop = prop
        self.helper = compat.gui().GuiUtil.QuantitySpinBox(widget, obj, prop)
        self.edited_text = None  # the last text the user typed
        line_edit = widget.findChild(QtGui.QLineEdit)
        if line_edit is not None:  # textEdited: the user's edits only
            line_edit.textEdited.connect(self._on_edited)

    def _on_edited(self, text):
        self.edited_text = text

    def to_property(self):
        self.helper.updateProperty()
        value = self.typed()
        prop = getattr(self.helper.obj, self.prop)
        if (
            value is not None and value != prop.Value and not self.helper.expression()
        ):  # the spin box rounded what the user typed
            setattr(self.helper.obj, self.prop, FreeCAD.Units.Quantity(value, prop.Unit))

    def from_property(self):
        compat.update_spin_box(self.helper)
        self.edited_text = None

    def _parse(self, text):
        text = (text or "").strip()
        if not text:  # FreeCAD parses "" as the smallest positive double
            return None
        try:
            quantity = FreeCAD.Units.Quantity(text)
        except (ValueError, ArithmeticError):
            return None
        expected = getattr(self.helper.obj, self.prop).Unit
        if quantity.Unit != expected and quantity.Unit != FreeCAD.Units.Unit():
            return None
        return quantity.Value

    def typed(self):
        """The value as typed, in mm (or the property's base unit); None if
        the text is not a quantity of the property's kind.

        FreeCAD 1.1's spin box rounds its text to the user's decimals (2 by
        default) when it loses focus: 0.002 mm typed shows as 0.00 mm. While
        the text shown is only that rounding of what the user typed, what
        the user typed counts."""
        shown = self._parse(self.widget.text())
        edited = self._parse(self.edited_text)
        if edited is not None and shown is not None and edited != shown:
            decimals = _decimals_shown(self.widget.text())
            if abs(edited - shown) <= 0.5 * 10.0**-decimals * (1 + 1e-9):
                return edited
        return shown

    def update_signals(self):
        return [self.widget.editingFinished]

    def live_signals(self):
        return [self.widget.textChanged]


def _decimals_shown(text):
    """Digits after the decimal separator in a spin box text like "0.00 mm"."""
    number = text.strip().split(" ")[0]
    for separator in (".", ","):
        if separator in number:
            tail = number.split(separator, 1)[1]
            return len(tail) - len(tail.lstrip("0123456789"))
    return 0


class EnumBinding:
    def __init__(self, widget, obj, prop):
        self.widget, self.obj, self.prop = widget, obj, prop
        blocker = QtCore.QSignalBlocker(widget)
        widget.clear()
        for value in obj.getEnumerationsOfProperty(prop):
            widget.addItem(value, value)
        del blocker

    def to_property(self):
        value = self.widget.currentData()
        if value is not None and getattr(self.obj, self.prop) != value:
            setattr(self.obj, self.prop, value)

    def from_property(self):
        blocker = QtCore.QSignalBlocker(self.widget)
        index = self.widget.findData(getattr(self.obj, self.prop))
        self.widget.setCurrentIndex(max(index, 0))
        del blocker

    def typed(self):
        return self.widget.currentData()

    def update_signals(self):
        return [self.widget.currentIndexChanged]

    live_signals = update_signals


class ValueBinding:
    """QCheckBox, QSpinBox or QDoubleSpinBox."""

    def __init__(self, widget, obj, prop):
        self.widget, self.obj, self.prop = widget, obj, prop
        self.is_check = isinstance(widget, QtGui.QCheckBox)

    def _widget_value(self):
        return self.widget.isChecked() if self.is_check else self.widget.value()

    def to_property(self):
        value = self._widget_value()
        if getattr(self.obj, self.prop) != value:
            setattr(self.obj, self.prop, value)

    def from_property(self):
        blocker = QtCore.QSignalBlocker(self.widget)
        value = getattr(self.obj, self.prop)
        if self.is_check:
            self.widget.setChecked(bool(value))
        else:
            self.widget.setValue(value)
        del blocker

    def typed(self):
        return self._widget_value()

    def update_signals(self):
        if self.is_check:
            return [self.widget.toggled]
        return [self.widget.editingFinished]

    def live_signals(self):
        return [self.widget.toggled if self.is_check else self.widget.valueChanged]


def _property_kind(obj, prop):
    type_id = obj.getTypeIdOfProperty(prop)
    if type_id == "App::PropertyEnumeration":
        return "enum"
    if any(kind in type_id for kind in QUANTITY_TYPES):
        return "quantity"
    if type_id == "App::PropertyBool":
        return "bool"
    if "Integer" in type_id or type_id == "App::PropertyPercent":
        return "int"
    return "float"


def _make_binding(widget, obj, prop):
    kind = _property_kind(obj, prop)
    if kind == "quantity":
        return QuantityBinding(widget, obj, prop)
    if kind == "enum":
        return EnumBinding(widget, obj, prop)
    return ValueBinding(widget, obj, prop)


def _new_widget(obj, prop):
    """A widget for `prop` in a generated page."""
    kind = _property_kind(obj, prop)
    if kind == "quantity":
        widget = FreeCADGui.UiLoader().createWidget("Gui::QuantitySpinBox")
        widget.setProperty("minimum", -1e9)
        widget.setProperty("maximum", 1e9)
    elif kind == "enum":
        widget = QtGui.QComboBox()
    elif kind == "bool":
        widget = QtGui.QCheckBox()
    elif kind == "int":
        widget = QtGui.QSpinBox()
        widget.setRange(-(2**31), 2**31 - 1)
    else:
        widget = QtGui.QDoubleSpinBox()
        widget.setRange(-1e9, 1e9)
        widget.setDecimals(4)
    widget.setObjectName(prop)
    return widget


# -- the operation's own page ---------------------------------------------------


class OperationPage(_base.TaskPanelPage):
    """The row's own page: its setup properties, tool controller, coolant,
    the live checks and the certificate."""

    def __init__(self, obj, features, spec):
        self.spec = spec
        self.bindings = {}
        self.messages = []  # reasons shown right now (tests read them)
        self.notice = ""  # e.g. "computation cancelled", until the next edit
        super().__init__(obj, features)

    # -- form ----------------------------------------------------------------

    def getForm(self):
        path = operations.panel_path(self.spec)
        if path:
            form = FreeCADGui.PySideUic.loadUi(path)
            qt_objects.true_type_children(form)
        else:
            form = self._generated_form()
        for name in ("validation", "certificate"):
            if form.findChild(QtGui.QLabel, name) is None:
                label = QtGui.QLabel()
                label.setObjectName(name)
                label.setWordWrap(True)
                form.layout().addWidget(label)
        form.setWindowTitle(self.spec.menu_text)
        return form

    def _generated_form(self):
        form = QtGui.QWidget()
        layout = QtGui.QFormLayout(form)
        for name, text in (
            ("toolController", "Tool Controller"),
            ("coolantController", "Coolant"),
        ):
            combo = QtGui.QComboBox()
            combo.setObjectName(name)
            layout.addRow(text, combo)
            setattr(form, name, combo)  # as loadUi does for a .ui file
        for prop in self._setup_properties():
            widget = _new_widget(self.obj, prop)
            layout.addRow(prop, widget)
            setattr(form, prop, widget)
        return form

    def _setup_properties(self):
        module = self.spec.import_module()
        return [p for p in module.SetupProperties() if hasattr(self.obj, p)]

    def _label(self, name):
        return self.form.findChild(QtGui.QLabel, name)

    # -- TaskPanelPage hooks ---------------------------------------------------

    def initPage(self, obj):
        for prop in self._setup_properties():
            widget = qt_objects.true_type(self.form.findChild(QtCore.QObject, prop))
            if widget is None:
                log.debug("%s panel has no widget for %s" % (self.spec.name, prop))
                continue
            if not widget.toolTip():
                widget.setToolTip(obj.getDocumentationOfProperty(prop))
            self.bindings[prop] = _make_binding(widget, obj, prop)

    def getFields(self, obj):
        for binding in self.bindings.values():
            binding.to_property()
        tc = self._chosen_tool_controller()
        if tc is not None and obj.ToolController != tc:
            obj.ToolController = tc
        if hasattr(self.form, "coolantController"):
            self.updateCoolant(obj, self.form.coolantController)

    def setFields(self, obj):
        for binding in self.bindings.values():
            binding.from_property()
        self._fill_tool_controllers(obj)
        if hasattr(self.form, "coolantController"):
            self.setupCoolant(obj, self.form.coolantController)
        self.validate()
        self.show_certificate()

    def getSignalsForUpdate(self, obj):
        signals = []
        for binding in self.bindings.values():
            signals.extend(binding.update_signals())
        for name in ("toolController", "coolantController"):
            if hasattr(self.form, name):
                signals.append(getattr(self.form, name).currentIndexChanged)
        return signals

    def registerSignalHandlers(self, obj):
        for binding in self.bindings.values():
            for signal in binding.live_signals():
                signal.connect(self._on_edit)
        if hasattr(self.form, "toolController"):
            self.form.toolController.currentIndexChanged.connect(self._on_edit)

    def updateData(self, obj, prop):
        if prop in ("Base", "ToolController"):
            self.validate()
        elif prop in self.output_names():
            self.show_certificate()

    def resetToolController(self, job, tc):
        # FreeCAD's Job tells every open page about a new tool controller.
        self._fill_tool_controllers(self.obj)

    # -- tool controllers -------------------------------------------------------

    def _fill_tool_controllers(self, obj):
        """The Job's tool controllers this op accepts, plus its current one
        even if it does not (so the page shows the problem instead of
        silently switching tools)."""
        combo = self.form.toolController
        job = compat.PathUtils.findParentJob(obj)
        controllers = list(job.Tools.Group) if job else []
        listed = [tc for tc in controllers if obj.Proxy.isToolSupported(obj, tc.Tool)]
        current = obj.ToolController
        if current is not None and current not in listed:
            listed.append(current)
        blocker = QtCore.QSignalBlocker(combo)
        combo.clear()
        for tc in listed:
            combo.addItem(tc.Label, tc.Name)
        if current is not None:
            combo.setCurrentIndex(combo.findData(current.Name))
        del blocker

    def _chosen_tool_controller(self):
        if not hasattr(self.form, "toolController"):
            return None
        name = self.form.toolController.currentData()
        return self.obj.Document.getObject(name) if name else None

    # -- checks and certificate ------------------------------------------------

    def _on_edit(self, *args):
        # Dirty as soon as something is typed: FreeCAD enables Apply only
        # for a dirty panel, and a disabled button cannot take the focus
        # that would end the field's editing.
        self.notice = ""
        self.setDirty()
        self.validate()

    def inputs(self):
        values = {prop: b.typed() for prop, b in self.bindings.items()}
        faces = [(base.Label, sub) for base, subs in (self.obj.Base or []) for sub in subs]
        return operations.Inputs(values, self._chosen_tool_controller(), faces)

    def validate(self):
        """Check the inputs as shown; put the reasons (or the hint) in the page."""
        inputs = self.inputs()
        self.messages = operations.check(self.spec, inputs)
        lines = []
        if self.notice:
            lines.append('<p style="color:#a05a00"><b>%s</b></p>' % _html(self.notice))
        if self.messages:
            lines.extend(
                '<p style="color:#c00000">&#9888; %s</p>' % _html(m) for m in self.messages
            )
        else:
            hint = operations.hint(self.spec, inputs)
            if hint:
                lines.append('<p style="color:#306030">%s</p>' % _html(hint))
        self._label("validation").setText("".join(lines))
        return self.messages

    def output_names(self):
        """The op's read-only outputs (its OUTPUTS rows, all in
        op_base.OUTPUT_GROUP), in their order."""
        rows = getattr(self.obj.Proxy, "OUTPUTS", ())
        return [row[1] for row in rows if hasattr(self.obj, row[1])]

    def show_certificate(self):
        rows = []
        computed = False
        for prop in self.output_names():
            value = getattr(self.obj, prop)
            shown = value.UserString if hasattr(value, "UserString") else str(value)
            computed = computed or bool(getattr(value, "Value", value))
            rows.append("<tr><td>%s</td><td>%s</td></tr>" % (prop, _html(shown)))
        label = self._label("certificate")
        if not rows:
            label.setText("")
        elif not computed:
            label.setText(
                "<i>%s</i>" % _html(translate("IsoCAM", "Certificate: not computed yet."))
            )
        else:
            label.setText(
                "<b>%s</b><table>%s</table>"
                % (_html(translate("IsoCAM", "Certificate")), "".join(rows))
            )

    def show_cancelled(self):
        self.notice = translate(
            "IsoCAM",
            "Computation cancelled: the operation keeps its previous path. "
            "Change the inputs and press OK or Apply again, or Cancel to "
            "discard the changes.",
        )
        self.validate()


def _html(text):
    return str(text).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


# -- the panel --------------------------------------------------------------------


class TaskPanel(_base.TaskPanel):
    """FreeCAD's operation panel, computing before it closes so that a cancel
    of the computation can keep it open."""

    def __init__(self, obj, deleteOnReject, opPage, selectionFactory):
        self.op_page = opPage
        super().__init__(obj, deleteOnReject, opPage, selectionFactory)

    def accept(self, resetEdit=True):
        if self.isDirty():
            self.panelGetFields()
        if not self._compute():
            return False  # stays open: the user cancelled the computation
        return super().accept(resetEdit)

    def clicked(self, button):
        if button != QtGui.QDialogButtonBox.Apply:
            return super().clicked(button)
        self.panelGetFields()
        self.setClean()
        if not self._compute():
            self.op_page.setDirty()

    def _compute(self):
        """Recompute the document; False if the user cancelled."""
        cancels = progress.user_cancels()
        self.obj.Document.recompute()
        if progress.user_cancels() != cancels:
            self.op_page.show_cancelled()
            return False
        return True
