"""The compiled kernels: built ahead of time into an extension module, else compiled by numba on first use.

The kernels are plain Python functions decorated with this module's `njit`,
which registers them: the modules that hold them (`slicelab.geometry.kernels`,
`slicelab.geometry.segment_kernels`, `slicelab.gcode.text_kernels`, ...) are
found by their import of it (`kernel_modules`), so this ground-floor module
names none of them. Each call goes to one of two compiled forms of
the same source:

- **ahead of time**: `build` compiles every kernel, for each argument type it
  is called with, into an extension module beside this file (numba's
  ``pycc``, which needs a C compiler), with a table of those types. Loading
  it needs no numba at run time, so a command skips numba's import and the
  first load of its cached kernels, which would cost more than many small
  parts take to slice.
- **just in time**: numba, compiled on the first call and cached on disk
  (`numba.njit`), for any argument types. It is used wherever the built
  module is missing (no compiler at install), stale (its sources' hash is not
  the sources' hash now) or has no entry for the arguments' types.

A call looks its arguments' types up in the table first (each array's dtype,
dimensions, layout and writability, each scalar's type, as numba types them),
so a compiled function only ever receives the types it was compiled for.

numba's forms are cached in the user's cache folder (`cache_dir`), not beside
the package, which may be read-only; a command that compiles them says so
once on stderr (`COMPILING`), and ``slicelab --version`` says which forms run
(`describe`). A wheel carries the built module: setup.py calls `build` when
the package is built.

See Also
--------
slicelab.geometry.kernels.warm : calls every kernel once with the types the layers use.

References
----------
.. [1] S. K. Lam, A. Pitrou, S. Seibert, "Numba: a LLVM-based Python JIT
   compiler", LLVM-HPC 2015 (``numba.pycc``: ahead-of-time compilation).
"""
from __future__ import annotations

import hashlib
import importlib
import json
import os
import sys
from pathlib import Path

import numpy as np

__all__ = ["njit", "Kernel", "build", "status", "select", "arguments_key", "kernel_modules", "cache_dir",
           "cached_kernels", "describe"]

#: The package whose modules are searched for kernels (by their import of this module's `njit`).
#: Name of the extension module `build` writes beside this file, and of its table.
EXTENSION = "_aot_kernels"
_HERE = Path(__file__).resolve().parent
_TABLE = _HERE / f"{EXTENSION}.json"

#: numba's types of Python scalars (on a 64-bit machine), as numpy dtype strings.
_SCALARS = {int: "<i8", float: "<f8", bool: "|b1"}


def arguments_key(args) -> tuple | None:
    """The types of a call's arguments as numba would type them: for an array its dtype,
    dimensions, layout ("C", "F" or "A") and writability, for a scalar its dtype; None if an
    argument is of another kind (the call then goes to numba).

    Examples
    --------
    >>> a = np.zeros((3, 2))
    >>> arguments_key((a, a[:, 0], 1, 2.0, True, np.float32(1)))
    (('<f8', 2, 'C', True), ('<f8', 1, 'A', True), '<i8', '<f8', '|b1', '<f4')
    """
    # Every kernel call passes here (some ninety a layer): a dtype's string is looked up, not
    # made again, and flags are read once per array.
    out = []
    for a in args:
        t = type(a)
        if t is _NDARRAY:
            d = a.dtype
            name = _DTYPES.get(d)
            if name is None:
                name = _DTYPES[d] = d.str
            f = a.flags
            out.append((name, a.ndim, "C" if f.c_contiguous else "F" if f.f_contiguous else "A", f.writeable))
        else:
            name = _SCALARS.get(t)
            if name is None:
                if not isinstance(a, np.generic):
                    return None
                name = a.dtype.str
            out.append(name)
    return tuple(out)


_NDARRAY = np.ndarray
_DTYPES: dict = {}


def _type_key(t) -> tuple | str | None:
    """`arguments_key`'s entry for a numba type (None: not one a call can be matched to)."""
    from numba.core import types
    if isinstance(t, types.Array):
        return (np.dtype(str(t.dtype)).str, t.ndim, t.layout, bool(t.mutable))
    if isinstance(t, (types.Integer, types.Float, types.Boolean)):
        return np.dtype(str(t)).str
    return None


def kernel_modules() -> tuple:
    """The modules of slicelab that define kernels (those that import this module's `njit`), as
    dotted names under the package: found in the sources, so that no list of them is kept here.

    Examples
    --------
    >>> "geometry.kernels" in kernel_modules()
    True
    """
    root = _HERE.parent
    found = []
    for path in sorted(root.rglob("*.py")):  # (the build and the stale check only: not at each start)
        text = path.read_text(encoding="utf-8")
        if "import njit" in text and path.name != "compiled.py":
            found.append(".".join(path.relative_to(root).with_suffix("").parts))
    return tuple(found)


def _sources_hash(modules) -> str:
    """A hash of the kernels' sources, of this module and of numpy's major version: a module built
    from other sources, or for another numpy, is not used. (The built module unboxes its arrays
    through numpy's C API, whose binary interface holds within a major version: a wheel built
    against one numpy 2 serves another; one a numpy too old cannot load fails to import, and is
    not used either.)"""
    h = hashlib.sha256(np.__version__.split(".")[0].encode())
    for name in (*modules, "geometry.compiled"):
        h.update((_HERE.parent / f"{name.replace('.', '/')}.py").read_bytes())
    return h.hexdigest()


class Kernel:
    """A kernel: its Python source, called through the built module or numba.

    Parameters
    ----------
    py_func : function
        The kernel as written.
    options : dict
        `numba.njit`'s options for the just-in-time form.
    """

    def __init__(self, py_func, options: dict):
        self.py_func = py_func
        self.options = options
        self.__name__ = py_func.__name__
        self.__qualname__ = py_func.__qualname__
        self.__module__ = py_func.__module__
        self.__doc__ = py_func.__doc__
        self.__wrapped__ = py_func
        self.table: dict | None = None  # arguments_key -> built function, from `_load`
        self.dispatcher = None  # the numba form, made on first need

    def __repr__(self) -> str:
        return f"<compiled kernel {self.__module__}.{self.__name__}>"

    def __call__(self, *args):
        table = self.table
        if table is None:  # the first call of any kernel: the built module is looked for
            status()
            table = self.table
        if table:
            f = table.get(arguments_key(args))
            if f is not None:
                return f(*args)
        return self.jit()(*args)

    def jit(self):
        """The numba form (compiled on first call, cached on disk), its module's kernels with it."""
        if self.dispatcher is None and self.__module__ in sys.modules:
            _jit_module(sys.modules[self.__module__])
        if self.dispatcher is None:  # a kernel its module does not hold (made elsewhere)
            self.dispatcher = _numba().njit(**self.options)(self.py_func)
        return self.dispatcher


def njit(**options):
    """Decorator making a function a `Kernel` (numba's `njit` options, for the just-in-time form).

    Examples
    --------
    >>> @njit(cache=False)
    ... def twice(a):
    ...     return 2 * a
    >>> twice(np.arange(3)).tolist()
    [0, 2, 4]
    """
    def decorate(fn):
        k = Kernel(fn, options)
        _REGISTRY[f"{fn.__module__.rpartition('.')[2]}.{fn.__name__}"] = k
        return k

    return decorate


def _jit_module(module) -> None:
    """numba forms of every kernel of a module, which it then holds in place of the kernels, so
    that numba, compiling one, finds the others it calls, its own or imported from another kernel
    module (and the intrinsics listed in the module's ``_NUMBA_GLOBALS``, name -> "module:attribute")."""
    numba = _numba()
    for name, where in getattr(module, "_NUMBA_GLOBALS", {}).items():
        mod, _, attr = where.partition(":")
        module.__dict__[name] = getattr(importlib.import_module(mod), attr)
    for name, value in list(vars(module).items()):
        if isinstance(value, Kernel) and value.__module__ == module.__name__:
            if value.dispatcher is None:
                value.dispatcher = numba.njit(**value.options)(value.py_func)
            module.__dict__[name] = value.dispatcher
    for name, value in list(vars(module).items()):  # kernels imported from another kernel module
        if isinstance(value, Kernel):
            module.__dict__[name] = value.jit()


#: Every kernel, by "module.function" (the module's last name).
_REGISTRY: dict = {}


def _kernels(modules=None) -> dict:
    """Every kernel registered (`njit`) by "module.function"; the kernel `modules` imported first."""
    for m in modules or ():
        importlib.import_module(f"slicelab.{m}")
    return dict(_REGISTRY)


def _load() -> str:
    """Attach the built module's functions to the kernels; say how it went."""
    for k in _kernels().values():
        k.table = {}
    if not _TABLE.exists():
        return "not built"
    try:
        table = json.loads(_TABLE.read_text())
        modules = table.get("modules", [])
        if table.get("sources") != _sources_hash(modules):
            return "stale (built from other sources)"
        ext = importlib.import_module(f"{__package__}.{EXTENSION}")
    except (OSError, ValueError, ImportError) as exc:
        return f"unusable ({type(exc).__name__}: {exc})"
    kernels = _kernels(modules)
    for qualname, entries in table["exports"].items():
        k = kernels.get(qualname)
        if k is not None:
            k.table = {_as_key(key): getattr(ext, export) for key, export in entries}
    return "loaded"


def _as_key(key: list) -> tuple:
    """A key as stored in JSON (lists) back to `arguments_key`'s tuples."""
    return tuple(tuple(k) if isinstance(k, list) else k for k in key)


_STATUS: list = []


def status() -> str:
    """Whether the kernels run from the built module: "loaded", "not built", "stale (...)",
    "unusable (...)" or "off" (the environment variable ``SLICELAB_JIT=1`` asks for numba alone).

    Examples
    --------
    >>> status() in ("loaded", "not built", "off") or status().startswith(("stale", "unusable"))
    True
    """
    if not _STATUS:
        if os.environ.get("SLICELAB_JIT") == "1":
            for k in _kernels().values():
                k.table = {}
            _STATUS.append("off")
        else:
            _STATUS.append(_load())
    return _STATUS[0]


def select(ahead_of_time: bool = True) -> str:
    """Look for the built module again (``ahead_of_time=True``) or leave every call to numba;
    return the new `status`.

    Examples
    --------
    >>> select(False)
    'off'
    >>> select() != 'off'
    True
    """
    _STATUS.clear()
    if not ahead_of_time:
        for k in _kernels().values():
            k.table = {}
        _STATUS.append("off")
    return status()


def build(*, quiet: bool = False) -> str:
    """Compile every kernel ahead of time into the extension module beside this file.

    The kernels are first compiled by numba and called by their modules' ``warm``
    (`slicelab.geometry.kernels.warm`, which also fills numba's disk cache, the fallback), then each is compiled ahead of
    time for every argument type numba has seen. Without a C compiler, or if anything
    fails, nothing is written and numba's forms serve.

    Returns
    -------
    str
        What was built, or why not.

    See Also
    --------
    status : whether a process runs the kernels from the built module.
    """
    import logging
    import tempfile
    import warnings

    names = kernel_modules()
    modules = [importlib.import_module(f"slicelab.{m}") for m in names]
    for module in modules:
        _jit_module(module)
    select(False)  # every call to numba, which records the types
    for module in modules:  # each module's kernels called with the types its callers pass
        if hasattr(module, "warm"):
            module.warm()
    exports, entries = [], {}
    try:
        from numba.core import types
        for qualname, k in _kernels(names).items():
            if k.__name__.startswith("_"):  # helpers: compiled into the kernels that call them
                continue
            d = k.jit()
            seen = set()
            for sig in d.signatures:
                # A literal argument (numba may type a constant 0 as Literal[int](0)) is built for
                # its type: a built function serves every value of it.
                args = tuple(types.unliteral(t) for t in sig)
                key = tuple(_type_key(t) for t in args)
                if any(x is None for x in key) or key in seen:
                    continue
                seen.add(key)
                name = f"{qualname.replace('.', '__')}__{len(seen) - 1}"
                exports.append((name, types.unliteral(d.overloads[sig].signature.return_type)(*args), k.py_func))
                entries.setdefault(qualname, []).append([key, name])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # pycc's pending deprecation
            logging.getLogger("numba").setLevel(logging.ERROR)
            from numba.pycc import CC
            with tempfile.TemporaryDirectory() as tmp:
                cc = CC(EXTENSION)
                cc.output_dir = tmp
                # The processor's baseline instructions (pycc's default), not this machine's own: the
                # module still runs if the installation moves to another x86-64 processor, and a
                # layer took the same time either way (scripts/profile_layers.py, alternating).
                cc.verbose = False
                for name, sig, fn in exports:
                    cc.export(name, sig)(fn)
                cc.compile()
                built = next(Path(tmp).glob(f"{EXTENSION}*"))
                target = _HERE / built.name
                os.replace(built, target) if built.stat().st_dev == _HERE.stat().st_dev \
                    else target.write_bytes(built.read_bytes())
    except Exception as exc:  # no compiler, no pycc: numba's forms serve
        _TABLE.unlink(missing_ok=True)
        why = str(exc).splitlines()[0] if str(exc) else ""
        msg = f"kernels not built ahead of time ({type(exc).__name__}: {why}); numba compiles them on first use"
        if not quiet:
            print(msg, file=sys.stderr)
        return msg
    tmp_table = _TABLE.with_suffix(".json.part")
    tmp_table.write_text(json.dumps({"sources": _sources_hash(names), "modules": list(names), "exports": entries}))
    os.replace(tmp_table, _TABLE)
    # This process goes on with numba's forms: an extension module, once imported, is not
    # imported again, so the new one serves from the next process on.
    return f"{len(exports)} kernel forms built ahead of time into {target.name}"


#: Said on stderr when numba starts compiling a kernel of slicelab in a process (once), with the
#: folder its forms are cached in: loading them from there later says nothing.
COMPILING = "slicelab: compiling the kernels with numba, once per installation (about a minute); cached in {}"
_NUMBA: list = []  # numba, once `_numba` has imported it
_NOTICED: list = []  # True once `COMPILING` has been said in this process


def cache_dir() -> Path:
    """The folder numba's just-in-time forms are cached in: ``NUMBA_CACHE_DIR`` where it is set,
    else slicelab's folder in the user's cache: ``$XDG_CACHE_HOME/slicelab/numba``, by default
    ``~/.cache/slicelab/numba`` (``~/Library/Caches/slicelab/numba`` on macOS,
    ``%LOCALAPPDATA%\\slicelab\\numba`` on Windows).

    Never beside the package, where numba caches by default: an installation may be read-only
    (a system's or a shared environment's site-packages), and every run would compile again.
    numba keeps each installation's forms apart (a subfolder per folder of sources).

    Examples
    --------
    >>> import os
    >>> cache_dir() == Path(os.environ["NUMBA_CACHE_DIR"]) if "NUMBA_CACHE_DIR" in os.environ else True
    True
    """
    given = os.environ.get("NUMBA_CACHE_DIR")
    if given:
        return Path(given).expanduser()
    home = Path(os.path.expanduser("~"))
    if sys.platform == "win32":
        root = Path(os.environ.get("LOCALAPPDATA") or home / "AppData" / "Local")
    elif sys.platform == "darwin":
        root = home / "Library" / "Caches"
    else:
        xdg = os.environ.get("XDG_CACHE_HOME", "")
        root = Path(xdg) if os.path.isabs(xdg) else home / ".cache"
    return root / "slicelab" / "numba"


def _numba():
    """numba, imported with its disk cache in `cache_dir` (``NUMBA_CACHE_DIR`` set for this process
    and those it starts, unless the user set it) and the notice of a compile (`COMPILING`) listening."""
    if _NUMBA:
        return _NUMBA[0]
    os.environ.setdefault("NUMBA_CACHE_DIR", str(cache_dir()))
    import numba
    from numba.core import config, event
    if not config.CACHE_DIR:  # numba was imported before, its environment read without it
        config.CACHE_DIR = os.environ["NUMBA_CACHE_DIR"]

    class CompileNotice(event.Listener):
        """Says `COMPILING` when numba compiles a kernel of slicelab (a cache miss): only then."""

        def on_start(self, ev):
            func = getattr(ev.data.get("dispatcher"), "py_func", None)
            if not _NOTICED and getattr(func, "__module__", "").startswith("slicelab."):
                _NOTICED.append(True)
                print(COMPILING.format(config.CACHE_DIR), file=sys.stderr, flush=True)

        def on_end(self, ev):
            pass

    event.register("numba:compile", CompileNotice())
    _NUMBA.append(numba)
    return numba


def cached_kernels() -> tuple[int, int]:
    """How many of the kernels numba has in its disk cache (`cache_dir`), of how many: those with
    an index (numba's ``.nbi`` file, named after the kernel's module, name and first line) newer
    than their source. Only files are read: numba is not imported.

    Examples
    --------
    >>> done, total = cached_kernels()
    >>> 0 <= done <= total and total > 10
    True
    """
    root = cache_dir()
    tag = f"py{sys.version_info[0]}{sys.version_info[1]}{getattr(sys, 'abiflags', '')}"
    kernels = _kernels(kernel_modules()).values()
    done = 0
    for k in kernels:
        code = k.py_func.__code__
        folder = os.path.dirname(os.path.abspath(code.co_filename))
        sub = f"{os.path.basename(folder)}_{hashlib.sha1(folder.encode()).hexdigest()}"
        stem = os.path.splitext(os.path.basename(code.co_filename))[0]
        index = root / sub / f"{stem}.{k.__qualname__}-{code.co_firstlineno}.{tag}.nbi"
        try:
            done += index.stat().st_mtime >= os.stat(code.co_filename).st_mtime
        except OSError:
            pass
    return done, len(kernels)


def describe() -> str:
    """Which compiled forms of the kernels a command runs, and where from, as ``slicelab --version``
    says it: the module built ahead of time (its file), or numba's (its cache folder, how many
    kernels it holds, and why the built module is not used).

    Examples
    --------
    >>> describe().startswith(("built ahead of time", "numba's"))
    True
    """
    state = status()
    if state == "loaded":
        return f"built ahead of time, {sys.modules[f'{__package__}.{EXTENSION}'].__file__}"
    done, total = cached_kernels()
    cached = ("none cached yet: the first command compiles them, about a minute" if done == 0
              else f"all {total} cached" if done == total else f"{done} of {total} cached")
    why = "as SLICELAB_JIT=1 asks" if state == "off" else f"the ahead-of-time module: {state}"
    return f"numba's, compiled on first use and cached in {cache_dir()} ({cached}); {why}"
