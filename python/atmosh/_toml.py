"""A small TOML writer for scene dicts (atmosh.atmo.atmosphere(dict)): tables, arrays
of tables ([[output]]), strings, booleans, integers, floats and flat lists of them.
The scene parser (C++, toml++) then validates the text as it does a scene file."""

import math

from . import _atmosh


def _value(v, key):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'
    if hasattr(v, "tolist"):  # numpy scalars and arrays
        return _value(v.tolist(), key)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x, key) for x in v) + "]"
    raise _atmosh.InputError("%s: a value of type %s has no TOML form" % (key, type(v).__name__))


def _is_table_list(v):
    return isinstance(v, (list, tuple)) and len(v) > 0 and all(isinstance(x, dict) for x in v)


def _emit(table, path, out):
    plain = [(k, v) for k, v in table.items() if not isinstance(v, dict) and not _is_table_list(v)]
    for k, v in plain:
        out.append("%s = %s" % (k, _value(v, ".".join(path + [k]))))
    for k, v in table.items():
        if isinstance(v, dict):
            out.append("")
            out.append("[%s]" % ".".join(path + [k]))
            _emit(v, path + [k], out)
        elif _is_table_list(v):
            for item in v:
                out.append("")
                out.append("[[%s]]" % ".".join(path + [k]))
                _emit(item, path + [k], out)


def dumps(scene):
    """TOML text of a nested dict."""
    if not isinstance(scene, dict):
        raise _atmosh.InputError("scene: expected a dict, got %s" % type(scene).__name__)
    out = []
    _emit(scene, [], out)
    return "\n".join(out) + "\n"
