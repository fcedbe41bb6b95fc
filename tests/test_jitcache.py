"""Numba's kernel cache is stamped with the whole package's sources (impactdyn._jitcache)."""

import subprocess
import sys

import pytest

from impactdyn import _jitcache

CHECK = """
import numba.core.caching as caching
from impactdyn.wall import _step
names = [c.__name__ for c in caching.CacheImpl._locator_classes]
locator = _step.node_pass._cache._impl._locator
print(names[:3] == ["PackageUserProvidedCacheLocator", "PackageInTreeCacheLocator", "PackageUserWideCacheLocator"],
      type(locator).__name__.startswith("Package"), names.count("PackageInTreeCacheLocator"))
"""


@pytest.mark.parametrize("first", ["impactdyn", "numba"])
def test_locators_are_installed_whichever_is_imported_first(first):
    out = subprocess.run([sys.executable, "-c", f"import {first}\nimport impactdyn\n" + CHECK],
                         capture_output=True, text=True, check=True).stdout.split()
    assert out == ["True", "True", "1"]


def test_import_impactdyn_does_not_import_numba():
    out = subprocess.run([sys.executable, "-c", "import sys, impactdyn; print('numba' in sys.modules)"],
                         capture_output=True, text=True, check=True).stdout.strip()
    assert out == "False"


def test_stamp_changes_with_any_package_source(monkeypatch):
    import numba.core.caching as caching
    from impactdyn.wall import _step

    _jitcache.install()
    locator = _step.node_pass._cache._impl._locator
    stamp = locator.get_source_stamp()
    assert stamp[1] == _jitcache.package_digest()
    # an edit of another file of the package (here: a different digest) makes the kernel's stamp stale
    monkeypatch.setattr(_jitcache, "package_digest", lambda: "edited")
    assert locator.get_source_stamp() != stamp
    assert locator.get_source_stamp()[0] == stamp[0]           # numba's own stamp of the defining file
    # functions outside the package keep numba's own locators
    package_classes = [c for c in caching.CacheImpl._locator_classes if getattr(c, "impactdyn_locator", False)]
    assert package_classes and all(c.from_function(test_stamp_changes_with_any_package_source, __file__) is None
                                   for c in package_classes)


def test_digest_covers_every_source_file():
    files = sorted(_jitcache.PACKAGE_DIR.rglob("*.py"))
    assert _jitcache.PACKAGE_DIR / "wall" / "_johnson_cook.py" in files
    assert all(_jitcache.in_package(str(f)) for f in files)
    assert not _jitcache.in_package(__file__)
    assert len(_jitcache.package_digest()) == 64


def test_an_index_that_no_longer_unpickles_is_read_as_a_stale_cache():
    """An index naming a record type since removed raised in every later process; it reads as empty."""
    from types import SimpleNamespace

    from impactdyn import _jitcache

    class IndexDataCacheFile:
        def _load_index(self):
            raise AttributeError("Can't get attribute 'Loads' on <module 'impactdyn.wall._state'>")

    caching = SimpleNamespace(IndexDataCacheFile=IndexDataCacheFile)
    _jitcache._tolerate_stale_indexes(caching)
    _jitcache._tolerate_stale_indexes(caching)  # once only: not wrapped twice
    assert IndexDataCacheFile()._load_index() == {}
    assert IndexDataCacheFile._load_index.impactdyn_tolerant
