"""User defaults for new IsoCAM operations, kept in FreeCAD's parameters.

Group ``User parameter:BaseApp/Preferences/Mod/IsoCAM/<OP_NAME>`` holds one
entry per setup property the user gave a default for (Edit > Preferences >
Path > IsoCAM writes them): lengths as floats in mm (FCFloat), enumerations
and other values as strings (FCText). A missing entry means "the operation's
built-in default".

Precedence when the GUI command makes an operation: the Job's SetupSheet (and
so a Job template) first, then these preferences, then the built-in default.
"""

import FreeCAD

from freecad_ext import compat
from freecad_ext.compat import translate

log = compat.logger(__name__)

GROUP = "User parameter:BaseApp/Preferences/Mod/IsoCAM"


def group(op_name):
    return FreeCAD.ParamGet("%s/%s" % (GROUP, op_name))


def stored_defaults(op_name):
    """{property: value} of the defaults the user set for `op_name`."""
    params = group(op_name)
    values = {}
    for name in params.GetFloats():
        values[name] = params.GetFloat(name)
    for name in params.GetStrings():
        values[name] = params.GetString(name)
    return values


def store_default(op_name, prop, value):
    """Save `value` (a float in mm, or a string) as the default of `prop`."""
    params = group(op_name)
    if isinstance(value, str):
        params.RemFloat(prop)
        params.SetString(prop, value)
    else:
        params.RemString(prop)
        params.SetFloat(prop, float(value))


def clear_default(op_name, prop):
    params = group(op_name)
    params.RemFloat(prop)
    params.RemString(prop)


def _sheet_has(job, op_name, prop):
    sheet = getattr(job, "SetupSheet", None) if job is not None else None
    if sheet is None:
        return False
    return hasattr(sheet, compat.PathSetupSheet.OpPropertyName(op_name, prop))


def _as_type_of(current, value):
    """`value` (a stored float or string) in the type of the property's
    `current` value: integer and boolean properties refuse floats."""
    if isinstance(current, bool):
        return bool(value)
    if isinstance(current, int) and isinstance(value, float):
        return int(round(value))
    return value


def apply_defaults(obj, op_name, setup_properties, job):
    """Give the new op `obj` the user's defaults, except where `job`'s
    SetupSheet has its own value. Returns the names of the properties set.

    A stored value the property refuses (e.g. an enumeration value that no
    longer exists) is reported and skipped.
    """
    applied = []
    for prop, value in stored_defaults(op_name).items():
        if prop not in setup_properties or not hasattr(obj, prop):
            continue
        if _sheet_has(job, op_name, prop):
            continue
        try:
            setattr(obj, prop, _as_type_of(getattr(obj, prop), value))
        except (ValueError, TypeError) as exc:
            log.warning(
                translate("IsoCAM", "preference %s/%s = %r ignored: %s")
                % (op_name, prop, value, exc)
            )
            continue
        applied.append(prop)
    return applied
