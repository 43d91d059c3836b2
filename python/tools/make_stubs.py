#!/usr/bin/python3
"""Writes a .pyi stub of a pybind11 module from its signatures and docstrings, so that
editors complete and type-check plantnbv. Usage: make_stubs.py MODULE OUT.pyi

The build runs it after linking the module: the stub always matches the module.
"""

import importlib
import inspect
import re
import sys

# pybind11's names for what our bindings take: any array-like (py::handle), any object.
TYPE_NAMES = {
    "handle": "numpy.typing.ArrayLike",
    "object": "typing.Any",
    "kwargs": "typing.Any",
    "args": "typing.Any",
    "capsule": "typing.Any",
    "Callable": "typing.Callable",
}


def clean_type(text, module_name):
    text = text.replace(module_name + ".", "")
    text = re.sub(r"numpy\.ndarray\[([^\]]*)\]", r"numpy.typing.NDArray[\1]", text)
    text = text.replace("NDArray[bool]", "NDArray[numpy.bool_]")
    for name in ("List", "Dict", "Tuple", "Optional", "Union", "Callable", "Iterator",
                 "Sequence"):
        text = re.sub(r"\b%s\[" % name, "typing.%s[" % name, text)
    words = re.split(r"(\W+)", text)
    return "".join(TYPE_NAMES.get(w, w) for w in words)


def split_top_level(text, separator=","):
    """Splits at separators outside brackets and quotes."""
    parts, depth, start, quote = [], 0, 0, None
    for i, c in enumerate(text):
        if quote:
            quote = None if c == quote else quote
        elif c in "'\"":
            quote = c
        elif c in "([{<":
            depth += 1
        elif c in ")]}>":
            depth -= 1
        elif depth == 0 and text.startswith(separator, i):
            parts.append(text[start:i])
            start = i + len(separator)
    parts.append(text[start:])
    return [p.strip() for p in parts if p.strip()]


def stub_signature(line, module_name, method):
    """'name(a: T, b: U = 1) -> R' -> ('name', '(self, a: T, b: U = ...) -> R')."""
    m = re.match(r"^(\w*)\((.*)\)(?:\s*->\s*(.+))?$", line.strip())
    if not m:
        return None
    name, params, result = m.group(1), m.group(2), m.group(3) or "None"
    out = []
    for i, p in enumerate(split_top_level(params)):
        if p in ("*", "/") or p.startswith("*"):
            out.append(p if p in ("*", "/") else p.split(":")[0])
            continue
        head, _, default = p.partition(" = ") if " = " in p else (p, "", "")
        pname, _, ptype = head.partition(":")
        pname = pname.strip()
        if method and i == 0 and pname in ("self", "arg0"):
            out.append("self")
            continue
        text = pname
        if ptype.strip():
            text += ": " + clean_type(ptype.strip(), module_name)
        if default:
            text += " = ..."
        out.append(text)
    return name, "(%s) -> %s" % (", ".join(out), clean_type(result, module_name))


def signatures(obj, module_name, method):
    doc = obj.__doc__ or ""
    lines = doc.splitlines()
    found = []
    if len(lines) > 1 and lines[1].strip() == "Overloaded function.":
        for line in lines:
            m = re.match(r"^\d+\. (.*)$", line)
            if m:
                found.append(stub_signature(m.group(1), module_name, method))
    elif lines:
        found.append(stub_signature(lines[0], module_name, method))
    return [f for f in found if f]


def docstring(obj, indent):
    doc = inspect.getdoc(obj) or ""
    lines = [l for l in doc.splitlines() if not re.match(r"^(\d+\. )?\w*\(.*\).*$", l)]
    text = "\n".join(lines).strip().replace('"""', "'''").replace("\\", "\\\\")
    return [indent + '"""%s"""' % text] if text else []


def function_stub(name, obj, module_name, indent, method=False, static=False):
    out = []
    sigs = signatures(obj, module_name, method and not static)
    for _, sig in sigs:
        if len(sigs) > 1:
            out.append(indent + "@typing.overload")
        if static:
            out.append(indent + "@staticmethod")
        out.append(indent + "def %s%s:" % (name, sig))
        body = docstring(obj, indent + "    ") or []
        out.extend(body + [indent + "    ..."] if body else [indent + "    ..."])
    if not sigs:
        out.append(indent + "def %s(*args: typing.Any, **kwargs: typing.Any) -> typing.Any: ..."
                   % name)
    return out


def class_stub(name, cls, module_name):
    bases = [b.__name__ for b in cls.__bases__ if b.__module__ == module_name]
    if issubclass(cls, BaseException):
        bases = [b.__qualname__ if b.__module__ == "builtins" else b.__name__
                 for b in cls.__bases__]
    out = ["class %s(%s):" % (name, ", ".join(bases)) if bases else "class %s:" % name]
    out += docstring(cls, "    ")
    if issubclass(cls, BaseException):
        return out + ["    ..."]
    for attr, value in cls.__dict__.items():
        if attr.startswith("__") and attr not in ("__init__", "__len__", "__iter__",
                                                  "__bool__", "__contains__"):
            continue
        if isinstance(value, property):
            sigs = signatures(value.fget, module_name, True) if value.fget else []
            kind = sigs[0][1].split("-> ", 1)[1] if sigs else "typing.Any"
            out.append("    @property")
            out.append("    def %s(self) -> %s:" % (attr, kind))
            out += docstring(value, "        ") + ["        ..."]
            if value.fset:
                out.append("    @%s.setter" % attr)
                out.append("    def %s(self, value: typing.Any) -> None: ..." % attr)
        elif isinstance(value, staticmethod):
            out += function_stub(attr, value.__func__, module_name, "    ", True, True)
        elif callable(value):
            out += function_stub(attr, value, module_name, "    ", True)
    return out + (["    ..."] if len(out) == 1 else [])


def main():
    module_name, path = sys.argv[1], sys.argv[2]
    module = importlib.import_module(module_name)
    out = ['"""Stubs of %s (generated by python/tools/make_stubs.py)."""' % module_name,
           "import os", "import typing", "", "import numpy", "import numpy.typing", ""]
    for name in sorted(dir(module)):
        if name.startswith("_"):
            continue
        value = getattr(module, name)
        if inspect.isclass(value):
            out += class_stub(name, value, module_name) + [""]
        elif callable(value):
            out += function_stub(name, value, module_name, "") + [""]
        else:
            out.append("%s: %s" % (name, type(value).__name__))
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
