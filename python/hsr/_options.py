"""Python keywords as the options of `hsr render`, which the compiled core parses as the command line
does: the same defaults, the same checks and the same messages."""

import numbers
import os

from ._hsr import UsageError

# A stand-in for the model on the command lines of a scene already loaded: the options are checked
# as for a render of a model, and the scene itself comes from the Scene object.
LOADED_SCENE = "loaded-scene"


def _is_integral(value):
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def integer(name, value):
    if _is_integral(value):
        return str(int(value))
    if isinstance(value, numbers.Real) and not isinstance(value, bool) and float(value).is_integer():
        return str(int(value))
    raise UsageError(f"{name}={value!r}: a whole number expected")


def number(name, value):
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return repr(float(value))
    raise UsageError(f"{name}={value!r}: a number expected")


def numbers_joined(name, value, count, separator=","):
    if isinstance(value, str):
        return value
    try:
        items = list(value)
    except TypeError:
        raise UsageError(f"{name}={value!r}: {count} numbers expected") from None
    if len(items) != count:
        raise UsageError(f"{name}={value!r}: {count} numbers expected")
    return separator.join(number(name, v) for v in items)


def color(name, value):
    """A colour as text ("r/g/b", "#rrggbb") or three numbers in [0, 1]."""
    return numbers_joined(name, value, 3, "/")


def setting_value(plugin, key, value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (tuple, list)):
        return color(f"{plugin}:{key}", value)
    return str(value)


def plugin_spec(name, spec, params):
    """The CLI's "name:key=value,..." of a plugin, with a dict of parameters added."""
    if not isinstance(spec, str) or not spec:
        raise UsageError(f"{name}={spec!r}: a plugin's name expected")
    if not params:
        return spec
    if not isinstance(params, dict):
        raise UsageError(f"{name} parameters: a dict expected, not {type(params).__name__}")
    settings = ",".join(f"{str(k).replace('_', '-')}={setting_value(spec, k, v)}" for k, v in params.items())
    return spec + ("," if ":" in spec else ":") + settings


def model_path(path):
    """A model's path as a command-line word: one that starts with '-' would read as an option."""
    text = os.fspath(path)
    if isinstance(text, bytes):
        text = os.fsdecode(text)
    return "./" + text if text.startswith("-") else text


def words(**options):
    """The command-line words of keyword options, those that are None left out (not given).

    Each keyword is the option's name with '_' for '-'; lists repeat the option."""
    out = []
    for key, value in options.items():
        if value is None:
            continue
        option = "--" + key.replace("_", "-")
        if isinstance(value, bool):
            if value:
                out.append(option)
            continue
        if isinstance(value, (list, tuple)) and key in _REPEATED:
            for item in value:
                out += [option, _REPEATED[key](key, item)]
            continue
        out += [option, _FORMAT.get(key, _text)(key, value)]
    return out


def _text(name, value):
    if isinstance(value, (str, os.PathLike)):
        return os.fspath(value)
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return number(name, value) if not _is_integral(value) else str(value)
    raise UsageError(f"{name}={value!r}: text expected")


def _light(name, value):
    if not isinstance(value, str):
        raise UsageError(f"{name}={value!r}: a light as hsr render --light takes it expected, e.g. 'dir:1,1,1'")
    return value


_FORMAT = {
    "width": integer, "height": integer, "samples": integer, "threads": integer, "step": integer,
    "random_triangles": integer, "seed": integer,
    "yaw": number, "pitch": number, "zoom": number, "fov": number, "near": number, "crease_angle": number,
    "opacity": number, "repeat_gap": number, "repeat_jitter": number, "line_width": number,
    "heightmap_height": number,
    "eye": lambda n, v: numbers_joined(n, v, 3), "target": lambda n, v: numbers_joined(n, v, 3),
    "up": lambda n, v: numbers_joined(n, v, 3),
    "background": color, "color": color, "line_color": color,
    "repeat": lambda n, v: v if isinstance(v, str) else "x".join(integer(n, k) for k in v),
    "camera": lambda n, v: str(v),
}
_REPEATED = {
    "light": _light,
    "section": number,
    "clip_plane": lambda n, v: numbers_joined(n, v, 4),
    "plugin_path": _text,
}
