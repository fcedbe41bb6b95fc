"""Every plug-in point is one :class:`impactdyn._registry.Registry` and follows the one idiom
(docs/extending.md): the same methods, a plug-in entered by ``register(name, plugin)``, an unknown
name refused with an InputError naming the key and every choice, a name registered twice refused."""

import pytest

from impactdyn._errors import InputError
from impactdyn._registry import Registry
from impactdyn.beam import CONTACT_LAWS
from impactdyn.ble import EQUATIONS
from impactdyn.debris import INTEGRATORS
from impactdyn.io import FORMATS
from impactdyn.materials import MATERIALS
from impactdyn.wall import FAILURE_LAWS, MODELS

#: Each registry and the case key that names one of its plug-ins (None: the registry says no key).
REGISTRIES = {"materials": (MATERIALS, None), "wall material models": (MODELS, "material_model"),
              "wall failure laws": (FAILURE_LAWS, "spall_law"), "debris integrators": (INTEGRATORS, "method"),
              "grid formats": (FORMATS, "format"), "beam contact laws": (CONTACT_LAWS, "model"),
              "ballistic-limit equations": (EQUATIONS, "equation")}


@pytest.fixture(params=sorted(REGISTRIES))
def registry(request):
    return REGISTRIES[request.param]


def test_every_registry_is_a_registry_with_plugins(registry):
    reg, key = registry
    assert isinstance(reg, Registry) and reg.key == key
    names = reg.names()
    assert names and len(set(names)) == len(names) == len(reg)
    assert list(reg) == list(names)
    for name in names:
        assert name in reg and reg.get(name) is reg[name]


def test_an_unknown_name_is_refused_naming_the_key_and_the_choices(registry):
    reg, key = registry
    with pytest.raises(InputError) as err:
        reg.get("no-such-plugin")
    message = str(err.value)
    assert "'no-such-plugin'" in message and reg.what in message
    assert all(name in message for name in reg.names())
    assert message.startswith(f"{key}: ") if key else not message.startswith(":")
    assert "no-such-plugin" not in reg
    with pytest.raises(InputError, match="^other.key: unknown"):
        reg.get("no-such-plugin", key="other.key")


def test_a_name_registered_twice_is_refused(registry):
    reg, _ = registry
    name = reg.names()[0]
    with pytest.raises(InputError, match="already registered"):
        reg.register(name, reg.get(name))
    assert reg.names()[0] == name


def test_register_and_unregister():
    reg = Registry("widget", "widget_kind", normalize=str.lower)
    assert reg.register("Spline", 1) == 1
    assert reg.get("spline") == 1 and reg.check("SPLINE") == "Spline" and reg.names() == ("Spline",)
    assert reg.register("spline", 2, replace=True) == 2 and reg.names() == ("spline",)
    assert reg.unregister("SPLINE") == 2 and len(reg) == 0
    with pytest.raises(InputError, match=r"^widget_kind: unknown widget 'spline'; choose one of $"):
        reg.get("spline")
