"""Python wrappers of Qt objects that name the object's own class.

PySide keeps one Python wrapper per C++ address. A wrapper made outside
PySide's own conversions (FreeCAD makes some in C++) is not told when its
widget is deleted; while something still holds it, a new widget that Qt
allocates at the same address is handed that old wrapper, with the old
class. We met it in FreeCAD 1.0: after the CAM simulator had been closed, the
"toolController" combo box of a freshly loaded panel came as a QDialog
(``'QDialog' object has no attribute 'addItem'``) and the panel did not
open. :func:`true_type` gives a wrapper of the object's own class instead.
"""

from PySide import QtCore, QtGui

try:  # FreeCAD 1.1 may run on PySide6
    import shiboken6 as _shiboken
except ImportError:
    try:
        import shiboken2 as _shiboken
    except ImportError:  # no shiboken module: wrappers are taken as given
        _shiboken = None


def _qt_class_name(cls):
    """The Qt class a wrapper class stands for (the first PySide class of
    its bases, so a Python subclass of QWidget gives QWidget)."""
    for base in cls.__mro__:
        if base.__module__.startswith(("PySide2.", "PySide6.")):
            return base.__name__
    return None


def _python_class(meta):
    """The PySide class of a C++ class, or of its nearest Qt base (a
    FreeCAD widget such as Gui::QuantitySpinBox gives QAbstractSpinBox)."""
    while meta is not None:
        name = meta.className()
        for module in (QtGui, QtCore):
            cls = getattr(module, name, None)
            if isinstance(cls, type):
                return cls
        meta = meta.superClass()
    return None


def true_type(obj):
    """`obj` itself when its wrapper's class is one the C++ object has;
    otherwise a new wrapper of the object's own class (None stays None)."""
    if obj is None or _shiboken is None or not _shiboken.isValid(obj):
        return obj
    name = _qt_class_name(type(obj))
    if name is None or obj.inherits(name):
        return obj
    cls = _python_class(obj.metaObject())
    if cls is None:
        return obj
    return _shiboken.wrapInstance(_shiboken.getCppPointer(obj)[0], cls)


def true_type_children(form):
    """Re-point the form's attributes (one per named child, as a loaded
    .ui gives) at wrappers of their children's own classes.

    The attributes are read from the form itself, not found again by
    findChildren: that converts every child to a wrapper, and for a child
    at the address of a deleted object it handed out the deleted object's
    wrapper, which raised "Internal C++ object (QDialogButtonBox) already
    deleted" (FreeCAD 0.20, a panel reopened after others had closed): the
    panel did not open. A wrapper that is no longer valid is left alone."""
    held = getattr(form, "__dict__", {})
    for name, obj in list(held.items()):
        if not isinstance(obj, QtCore.QObject):
            continue
        try:
            fixed = true_type(obj)
        except RuntimeError:  # its object is gone: nothing to re-point
            continue
        if fixed is not obj:
            setattr(form, name, fixed)
