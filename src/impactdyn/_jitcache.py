"""Numba's on-disk kernel cache, stamped with every source file of the package.

Numba (``cache=True``) stamps a cached kernel with a hash of the one file that defines it and
loads it again while that file is unchanged — even after a function it calls or inlines from
another module has changed.  The wall's element pass (:mod:`impactdyn.wall._step`) inlines the
material updates of ``wall._johnson_cook`` and ``wall._mat13`` and the kernels of
:mod:`impactdyn.constitutive`; after an edit of those files alone it ran the old machine code
(a new failure criterion went unrecorded until the cache was deleted).  A user upgrading impactdyn in place keeps numba's cache files, which pip does not
remove, and would meet the same.

The locators here, put in front of numba's own for the functions defined in this package (and
only those), stamp a kernel with numba's own stamp together with a digest of all the package's
Python sources: a change anywhere in the package recompiles its kernels once, and a cached
kernel never outlives the code it was compiled from.  They are installed as soon as numba's
caching module is imported (:func:`install_on_numba_import`, called by the package's
``__init__``), so ``import impactdyn`` still does not import numba.  They use numba's
``CacheImpl._locator_classes`` (numba.core.caching, a private list); should a numba release drop
it, caching falls back to numba's own behaviour with a warning.
"""

from __future__ import annotations

import hashlib
import importlib.abc
import importlib.util
import sys
import types
import warnings
from functools import lru_cache
from pathlib import Path

PACKAGE_DIR = Path(__file__).resolve().parent
_CACHING = "numba.core.caching"


@lru_cache(maxsize=1)
def package_digest() -> str:
    """SHA-256 of the package's Python sources (relative paths and contents, in path order)."""
    h = hashlib.sha256()
    for path in sorted(PACKAGE_DIR.rglob("*.py")):
        h.update(path.relative_to(PACKAGE_DIR).as_posix().encode() + b"\0")
        h.update(path.read_bytes())
    return h.hexdigest()


def in_package(py_file: str) -> bool:
    """Whether ``py_file`` is a source file of this package."""
    try:
        Path(py_file).resolve().relative_to(PACKAGE_DIR)
    except (ValueError, OSError):
        return False
    return True


def bind_globals(template, suffix: str, **names):
    """A copy of the function ``template`` that sees ``names`` in place of its module's globals of
    those names, with the qualified name ``template.__qualname__ + "[" + suffix + "]"`` (numba's
    cache file is named by it): how a compiled template takes a plug-in's kernel (a wall model's update,
    a failure law's increment) as a global of its code rather than an argument or a closure's cell,
    whose dispatcher would defeat numba's cache (:func:`impactdyn.wall._step.step_kernels`)."""
    fn = types.FunctionType(template.__code__, {**template.__globals__, **names}, template.__name__)
    fn.__qualname__ = f"{template.__qualname__}[{suffix}]"
    fn.__module__ = template.__module__
    fn.__doc__ = template.__doc__
    return fn


def _package_locator(base: type) -> type:
    """A subclass of numba's locator ``base`` that takes only this package's functions and adds
    :func:`package_digest` to their stamp."""

    class PackageLocator(base):
        impactdyn_locator = True

        @classmethod
        def from_function(cls, py_func, py_file):
            return super().from_function(py_func, py_file) if in_package(py_file) else None

        def get_source_stamp(self):
            return super().get_source_stamp(), package_digest()

    PackageLocator.__name__ = PackageLocator.__qualname__ = f"Package{base.__name__}"
    return PackageLocator


def install(caching=None) -> bool:
    """Put the package's locators in front of numba's (once); True if they are in place."""
    if caching is None:
        import numba.core.caching as caching
    try:
        classes = caching.CacheImpl._locator_classes
        bases = (caching.UserProvidedCacheLocator, caching.InTreeCacheLocator, caching.UserWideCacheLocator)
    except AttributeError:
        warnings.warn("impactdyn: numba's cache locators have moved; cached kernels are stamped by their own "
                      "file only (delete numba's cache after changing impactdyn)", RuntimeWarning, stacklevel=2)
        return False
    if not any(getattr(c, "impactdyn_locator", False) for c in classes):
        classes[:0] = [_package_locator(b) for b in bases]
    _tolerate_stale_indexes(caching)
    return True


def _tolerate_stale_indexes(caching) -> None:
    """A cache index that no longer unpickles is a stale cache, not an error.

    Numba unpickles a kernel's index, the argument types of its cached overloads included, before it
    compares the source stamp, so an index written by other sources whose record types have since been
    renamed or removed raised in every later process (``AttributeError: Can't get attribute 'Loads' on
    impactdyn.wall._state`` after the wall's load record was merged into ``NodalLoad``): a user upgrading
    in place would meet it.  Such an index is read as empty, so the kernel is compiled and its cache
    written anew, as for any stale stamp (``IndexDataCacheFile._load_index``, numba.core.caching,
    private; left alone if it moves)."""
    cache_file = getattr(caching, "IndexDataCacheFile", None)
    load = getattr(cache_file, "_load_index", None)
    if load is None or getattr(load, "impactdyn_tolerant", False):
        return

    def _load_index(self):
        try:
            return load(self)
        except Exception:  # noqa: BLE001 - whatever an outdated pickle raises, it is a stale cache
            return {}

    _load_index.impactdyn_tolerant = True
    cache_file._load_index = _load_index


class _InstallAfterCaching(importlib.abc.MetaPathFinder):
    """Finds numba's caching module by the other finders and installs the locators once it has run."""

    def find_spec(self, name, path=None, target=None):
        if name != _CACHING:
            return None
        sys.meta_path.remove(self)
        spec = importlib.util.find_spec(name)
        if spec is None or spec.loader is None:
            return spec
        run = spec.loader.exec_module

        def exec_module(module):
            run(module)
            install(module)

        spec.loader.exec_module = exec_module
        return spec


def install_on_numba_import() -> None:
    """Install the locators now if numba's caching module is loaded, else as soon as it is.

    The digest is taken now, as the package is imported, not when the first kernel is cached: a
    process that imported the old sources and hashed the files after they were edited would store
    the old machine code under the new sources' digest, and the next process would run it on the
    new code's data layout and die of a general-protection fault."""
    package_digest()
    if _CACHING in sys.modules:
        install(sys.modules[_CACHING])
    elif not any(isinstance(f, _InstallAfterCaching) for f in sys.meta_path):
        sys.meta_path.insert(0, _InstallAfterCaching())
