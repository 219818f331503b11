"""A scene given as a Python dict: written out as TOML text with the same
keys, so that the scene loader checks it with the same code and the same
messages; the positions in those messages (line:column of the generated
text) are mapped back to the key path in the dict."""
import datetime
import json
import math
import re
from collections.abc import Mapping

from .errors import InputError

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")
SOURCE = "dict"


def _key(k, path):
    if not isinstance(k, str):
        raise InputError(f"{key_label(path)}: error: keys must be strings, not {type(k).__name__} {k!r}", key=path)
    return k if _BARE_KEY.match(k) else json.dumps(k, ensure_ascii=False)


def key_label(path):
    return "scene" + "".join(f"[{p!r}]" for p in path)


def _is_table_array(v):
    return isinstance(v, (list, tuple)) and len(v) > 0 and all(isinstance(x, Mapping) for x in v)


def _value(v, path):
    try:
        import numpy as np
        if isinstance(v, np.ndarray):
            v = v.tolist()
        elif isinstance(v, np.generic):
            v = v.item()
    except ImportError:  # pragma: no cover
        pass
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
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, (datetime.datetime, datetime.date, datetime.time)):
        return v.isoformat()
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x, path + (i,)) for i, x in enumerate(v)) + "]"
    if isinstance(v, Mapping):
        return "{" + ", ".join(f"{_key(k, path)} = {_value(x, path + (k,))}" for k, x in v.items()) + "}"
    raise InputError(f"{key_label(path)}: error: {type(v).__name__} {v!r} has no TOML form "
                     "(give a number, string, boolean, list or dict)", key=path)


def to_toml(scene):
    """(text, where): TOML text of a scene dict, and for each line the key path it holds."""
    if not isinstance(scene, Mapping):
        raise InputError(f"scene: error: a scene dict must be a mapping, not {type(scene).__name__}", key=())
    lines = ["# a scene given as a Python dict"]
    where = [()]

    def table(path, header_path, t):
        for k, v in t.items():
            if not isinstance(v, Mapping) and not _is_table_array(v):
                lines.append(f"{_key(k, path)} = {_value(v, path + (k,))}")
                where.append(path + (k,))
        for k, v in t.items():
            header = header_path + (_key(k, path),)
            if isinstance(v, Mapping):
                lines.append("[" + ".".join(header) + "]")
                where.append(path + (k,))
                table(path + (k,), header, v)
            elif _is_table_array(v):
                for i, item in enumerate(v):
                    lines.append("[[" + ".".join(header) + "]]")
                    where.append(path + (k, i))
                    table(path + (k, i), header, item)

    table((), (), scene)
    return "\n".join(lines) + "\n", where


_POSITION = re.compile(r"^" + re.escape(SOURCE) + r":(\d+):(\d+): (error|warning): ", re.M)


def relabel(message, where):
    """The loader's message with 'dict:LINE:COL' replaced by the key path; (message, key path)."""
    found = []

    def sub(m):
        line = int(m.group(1))
        path = where[line - 1] if 1 <= line <= len(where) else ()
        found.append(path)
        return f"{key_label(path)}: {m.group(3)}: "

    text = _POSITION.sub(sub, message)
    return text, (found[0] if found else None)
