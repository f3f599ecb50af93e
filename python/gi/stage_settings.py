"""The renderer's own settings a stage carries on its render settings prim, as hdGi reads them
through Hydra (hdGi/renderSettings.cpp): `gi:integrator`, `gi:samples`, `gi:seed`,
`gi:timeLimit`, `gi:preset` and `gi:<integrator>:<parameter>`. `gi render` takes them as its
defaults, so a stage renders the same through usdrecord and `gi render`; a flag given on the
command line wins. An unknown gi: attribute warns naming the prim (a typo must not leave a
parameter at its default unseen)."""
from dataclasses import dataclass, field

FIXED = {"gi:integrator": "integrator", "gi:samples": "spp", "gi:seed": "seed", "gi:timeLimit": "time_limit",
         "gi:preset": "preset"}
# Hydra's own settings a stage may carry beside them (read by hdGi, not by `gi render`).
HYDRA_ONLY = {"gi:denoise"}


@dataclass
class StageSettings:
    values: dict = field(default_factory=dict)   # render flag dest -> value (spp, seed, ...)
    params: dict = field(default_factory=dict)   # integrator -> {parameter: value}


def read_stage_settings(settings, catalog, warn):
    """The gi: attributes of `settings` (a UsdRender.Settings, or None) at the default time.
    `catalog`: the integrators and their parameters (gi.render.integrator_catalog())."""
    found = StageSettings()
    if settings is None:
        return found
    prim = settings.GetPrim()
    taken = {info["name"]: {p["name"] for p in info["params"]} for info in catalog}
    for attribute in prim.GetAttributes():
        name = attribute.GetName()
        if not name.startswith("gi:") or not attribute.HasAuthoredValue():
            continue
        value = attribute.Get()
        if name in FIXED:
            found.values[FIXED[name]] = str(value) if FIXED[name] in ("integrator", "preset") else value
            continue
        if name in HYDRA_ONLY:
            continue
        parts = name.split(":")
        if len(parts) == 3 and parts[1] in taken and parts[2] in taken[parts[1]]:
            found.params.setdefault(parts[1], {})[parts[2]] = value
            continue
        warn(f"{prim.GetPath()}: unknown setting {name} (gi:integrator, gi:samples, gi:seed, gi:timeLimit, "
             f"gi:preset, gi:denoise or gi:<integrator>:<parameter>); ignored")
    return found
