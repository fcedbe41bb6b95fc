"""The one plug-in idiom: a :class:`Registry` of named plug-ins.

Every extension point of the package — materials, wall material models, wall failure laws, debris
integrators, grid formats — is a ``Registry``, and every plug-in enters it the same way, by one call at
the bottom of the module that defines it (as meshio's formats do)::

    FAILURE_LAWS.register("cutoff", CUTOFF)        # the registry's own name for the key, the plug-in

A plug-in is whatever its registry holds (a record, a class, a function): it brings its own code, its
constants and its description, so that adding one touches no other module.  Lookups go through
:meth:`Registry.get`, which refuses an unknown name with an :class:`~impactdyn._errors.InputError` naming
the case key (or argument) at fault and the registered choices; a registry reads like a mapping
(``name in registry``, iteration over the names, ``registry[name]``, ``len``) so that tests and command-line
choices take its names from it.  See docs/extending.md.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Annotated, Any, Generic, TypeVar

from pydantic import AfterValidator

from impactdyn._errors import InputError

T = TypeVar("T")


class Registry(Generic[T]):
    """Named plug-ins of one kind.

    what : what a plug-in is, for messages ("wall failure law").
    key : the case key or argument that names one ("spall_law"), prefixed to the refusal of an unknown name.
    normalize : maps a name to its lookup key (default: the name itself); materials ignore case and separators.
    load : called before every lookup, once the package is imported (grid formats import their
        built-in modules lazily, so that ``import impactdyn.io`` loads no format).
    hint : appended to the refusal of an unknown name (where a user can define one).
    """

    def __init__(self, what: str, key: str | None = None, *, normalize: Callable[[str], str] | None = None,
                 load: Callable[[], None] | None = None, hint: str = ""):
        self.what, self.key, self.hint = what, key, hint
        self._normalize = normalize or (lambda name: name)
        self._load = load
        self._items: dict[str, T] = {}

    # -- registration ---------------------------------------------------------------------------
    def register(self, name: str, plugin: T, *, replace: bool = False) -> T:
        """Enter ``plugin`` under ``name`` and return it.  A name already registered (as the registry's
        ``normalize`` sees it) raises :class:`InputError` (a ``ValueError``) unless ``replace``: then the
        old entry goes."""
        if not isinstance(name, str) or not self._normalize(name):
            raise InputError(f"{self.what}: the name {name!r} needs a letter or digit")
        known = self._find(name)
        if known is not None:
            if not replace:
                raise InputError(f"{self.what} {name!r} is already registered (as {known!r}); choose another name")
            del self._items[known]
        self._items[name] = plugin
        return plugin

    def unregister(self, name: str) -> T:
        """Remove ``name`` and return its plug-in (a test's own plug-in, once the test is done)."""
        return self._items.pop(self._find(name) or name)

    # -- lookup ---------------------------------------------------------------------------------
    def get(self, name: str, key: str | None = None) -> T:
        """The plug-in registered as ``name``; an unknown name raises :class:`InputError` naming ``key``
        (default the registry's) and the registered choices."""
        known = self._canonical(name) if isinstance(name, str) else None
        if known is None:
            raise InputError(self.unknown(name, key))
        return self._items[known]

    def check(self, name: str, key: str | None = None) -> str:
        """The registered name of ``name`` (as :meth:`get`)."""
        self.get(name, key)
        return self._canonical(name)

    def name_type(self) -> Any:
        """A pydantic type of a config key that names one of these plug-ins: ``Annotated[str, …]`` whose
        validator refuses an unknown name with the choices and stores the registered name."""
        def registered(name: str) -> str:
            if name not in self:
                raise ValueError(self.unknown(name, key=""))
            return self.check(name)

        registered.registry = self  # the docs' reference lists the registered names (docs/_ext)
        return Annotated[str, AfterValidator(registered)]

    def unknown(self, name: object, key: str | None = None) -> str:
        """The refusal of an unknown ``name``: the key, the name and the choices."""
        key = key if key is not None else self.key
        prefix = f"{key}: " if key else ""
        hint = f" ({self.hint})" if self.hint else ""
        return f"{prefix}unknown {self.what} {name!r}; choose one of {', '.join(self.names())}{hint}"

    def names(self) -> tuple[str, ...]:
        """The registered names, in the order they were registered."""
        self._loaded()
        return tuple(self._items)

    def items(self):
        self._loaded()
        return dict(self._items).items()

    def values(self):
        self._loaded()
        return list(self._items.values())

    def keys(self):
        return self.names()

    def __getitem__(self, name: str) -> T:
        return self.get(name)

    def __contains__(self, name: object) -> bool:
        return isinstance(name, str) and self._canonical(name) is not None

    def __iter__(self) -> Iterator[str]:
        return iter(self.names())

    def __len__(self) -> int:
        return len(self.names())

    def __repr__(self) -> str:
        return f"Registry({self.what!r}: {', '.join(self._items)})"

    def _loaded(self) -> None:
        if self._load is not None:
            self._load()

    def _canonical(self, name: str) -> str | None:
        self._loaded()
        return self._find(name)

    def _find(self, name: str) -> str | None:
        if name in self._items:
            return name
        key = self._normalize(name)
        return next((known for known in self._items if self._normalize(known) == key), None)
