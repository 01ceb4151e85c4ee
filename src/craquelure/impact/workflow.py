"""Helpers of ``workflow/rules/impact.smk`` (so the rule file holds rules only): run paths from
the ``impact`` config section, and the `--set` arguments of one run from its wildcards."""

from __future__ import annotations

import shlex


def seeds(section: dict) -> list[int]:
    return list(range(section["first_seed"], section["first_seed"] + section["n_seeds"]))


# The source's support-domain multipliers (its Figs. 7-10); check 12 compares these cases.
SOURCE_KAPPAS = (0.7, 1.0, 1.5)


def case_key(masses: str, precrack: str, kappa) -> str:
    """Key of one case in summary.json and check 12: ``<masses>/<pre-crack>/kappa<k:g>``."""
    return f"{masses}/{precrack}/kappa{float(kappa):g}"


def case_folder(masses: str, precrack: str, kappa) -> str:
    """Folder of one case's runs, ``<masses>_<pre-crack>/kappa<k>`` (k as the config writes
    it; with ``"{masses}"`` etc.: the rules' wildcard pattern)."""
    return f"{masses}_{precrack}/kappa{kappa}"


def run_path(scene: str, masses: str, precrack: str, kappa: float, seed: int) -> str:
    return f"results/impact/{scene}/{case_folder(masses, precrack, kappa)}/seed{seed}.nc"


def campaign_runs(section: dict) -> list[str]:
    """The homogeneous disc (seed 0) for each kappa and pre-crack; the heterogeneous seeds at
    ``heterogeneous_kappas``, with pre-cracks if ``precrack_heterogeneous``. Pre-crack layouts
    run at ``precrack_kappas`` only (both lists default to every kappa)."""
    scene = section["scene"]
    hetero_kappas = section.get("heterogeneous_kappas", section["kappas"])
    precrack_kappas = section.get("precrack_kappas", section["kappas"])
    if not set(precrack_kappas) <= set(section["kappas"]):
        raise ValueError(f"impact precrack_kappas {list(precrack_kappas)}: each must be one of "
                         f"the kappas {list(section['kappas'])}")
    runs = []
    for kappa in section["kappas"]:
        layouts = section["precracks"] if kappa in precrack_kappas else []
        for precrack in ["none", *layouts]:
            runs.append(run_path(scene, "homogeneous", precrack, kappa, 0))
            if kappa in hetero_kappas and (precrack == "none"
                                           or section.get("precrack_heterogeneous", False)):
                runs += [run_path(scene, section["distribution"], precrack, kappa, s)
                         for s in seeds(section)]
    return runs


def three_d(section: dict) -> dict | None:
    """The 3D campaign (``impact.three_d`` over the section's keys); None without 3D."""
    return {**section, **section["three_d"]} if 3 in section.get("dims", [2]) else None


def campaign_runs_3d(section: dict) -> list[str]:
    """The 3D campaign's runs (:func:`campaign_runs` of :func:`three_d`); none without 3D."""
    return campaign_runs(cfg) if (cfg := three_d(section)) is not None else []


def with_rate_effects(section: dict) -> dict | None:
    """The campaign again with CSCM's rate effects (config ``impact.rate``: the 2D ``scene``
    and ``three_d.scene`` to use instead), or None without ``impact.rate``."""
    if not (rate := section.get("rate")):
        return None
    return {**section, "scene": rate["scene"],
            "three_d": {**section.get("three_d", {}), **rate.get("three_d", {})}}


def three_d_scenes(section: dict) -> set[str]:
    """The 3D campaign's scene and, with ``impact.rate``, its rate-effects twin."""
    cfgs = (three_d(section), three_d(with_rate_effects(section) or {"dims": []}))
    return {cfg["scene"] for cfg in cfgs if cfg is not None}


def three_d_overrides(section: dict):
    """`--set` arguments of ``three_d.set`` for runs of the 3D campaign's scenes."""
    cfg, scenes = three_d(section), three_d_scenes(section)

    def overrides(wildcards) -> str:
        if wildcards.scene not in scenes:
            return ""
        return " ".join(f"--set {shlex.quote(item)}" for item in cfg.get("set", []))
    return overrides


def _scene_value(section: dict, key: str, cfg: dict | None, scenes: set[str]):
    """A function of the wildcards: ``cfg[key]`` for runs of ``scenes``, else the section's."""
    def value(wildcards) -> int:
        return cfg[key] if wildcards.scene in scenes else section[key]
    return value


def run_resource(section: dict, key: str):
    """Per-run resources of rule impact_run: the 3D campaign's for runs of its scenes."""
    return _scene_value(section, key, three_d(section), three_d_scenes(section))


def figure_runs(section: dict) -> dict:
    """Runs drawn in the report figures, by role."""
    scene, hetero = section["scene"], section["distribution"]
    shown = seeds(section)[:4]
    kappas = section["kappas"]
    one = 1.0 if 1.0 in kappas else kappas[0]
    return {
        "specimen": run_path(scene, hetero, "none", one, shown[0]),
        "homogeneous": [run_path(scene, "homogeneous", "none", k, 0) for k in kappas],
        "hetero_kappa1": [run_path(scene, hetero, "none", one, s) for s in shown],
        "hetero_low_high": [run_path(scene, hetero, "none", k, s)
                            for k in kappas if k != one for s in shown[:2]]
        or [run_path(scene, hetero, "none", one, shown[0])],
        "precracks": [run_path(scene, "homogeneous", p, one, 0) for p in section["precracks"]]
        or [run_path(scene, "homogeneous", "none", one, 0)],
        "contact": [run_path(scene, m, "none", k, s) for k in kappas
                    for m, s in (("homogeneous", 0), (hetero, shown[0]))],
    }


def judged_runs(section: dict) -> dict:
    """Runs drawn in the pictures of what check 12 judges (the 3D campaign's when ``dims`` has
    3, the 2D one's otherwise): ``maps`` every disc at each kappa, ``sequence`` one seed per
    variant, ``energy`` the homogeneous kappa = 1 disc."""
    cfg = three_d(section) or section
    scene, hetero = cfg["scene"], cfg["distribution"]
    kappas, one = cfg["kappas"], 1.0 if 1.0 in cfg["kappas"] else cfg["kappas"][0]
    hetero_kappas = cfg.get("heterogeneous_kappas", kappas)
    layouts = cfg["precracks"] if one in cfg.get("precrack_kappas", kappas) else []
    first = seeds(cfg)[:1] if one in hetero_kappas else []
    return {
        "maps": [run_path(scene, m, "none", k, s) for k in kappas
                 for m, ss in (("homogeneous", [0]),
                               (hetero, seeds(cfg) if k in hetero_kappas else []))
                 for s in ss],
        "sequence": [run_path(scene, "homogeneous", "none", k, 0) for k in kappas]
        + [run_path(scene, hetero, "none", one, s) for s in first]
        + [run_path(scene, "homogeneous", p, one, 0) for p in layouts],
        "energy": run_path(scene, "homogeneous", "none", one, 0),
    }


FIXED_KEYS = {"as_epsilon": "numerics.as_epsilon", "crack_band_width": "material.crack_band_width"}


def variant_overrides(section: dict):
    """`--set` arguments of one variant from its wildcards and ``fixed_across_kappa``."""
    fixed = " ".join(f"--set {FIXED_KEYS[k]}={v!r}" for k, v in
                     sorted((section.get("fixed_across_kappa") or {}).items()))

    def overrides(wildcards) -> str:
        return (f"--set particles.masses.distribution={wildcards.masses} "
                f"--set particles.precrack={wildcards.precrack} "
                f"--set numerics.kappa={wildcards.kappa}" + (f" {fixed}" if fixed else ""))
    return overrides


def regime_path(scene: str, f_t: float, a, v: float) -> str:
    """One regime run: f_t in Pa (written in MPa), penalty scale a (number or ``auto``), speed."""
    return f"results/impact/{scene}/regime/ft{f_t / 1e6:g}_a{a}_v{v:g}.nc"


def _grid_runs(scene: str, grid: dict) -> list[str]:
    return [regime_path(scene, f_t, a, v)
            for f_t in grid["f_t"] for a in grid["contact_a"] for v in grid["velocities"]]


def regime_runs(section: dict) -> list[str]:
    """Runs of the 2D regime map (config ``impact.regime``): f_t x contact_a x speed."""
    return _grid_runs(section["scene"], section["regime"])


def regime_three_d(section: dict) -> dict | None:
    """The 3D regime grid (``impact.regime.three_d`` over the 2D grid's keys); None without."""
    reg = section["regime"]
    if "three_d" not in reg or 3 not in section.get("dims", [2]):
        return None
    cfg = {**{k: v for k, v in reg.items() if k != "three_d"}, **reg["three_d"]}
    if cfg["scene"] == section["scene"]:
        raise ValueError(f"impact.regime.three_d.scene: {cfg['scene']!r} is the 2D scene; the "
                         "3D regime map needs its own 3D scene (domain.dim 3), e.g. disc3d")
    return cfg


def regime_runs_3d(section: dict) -> list[str]:
    """Runs of the 3D regime map (:func:`regime_three_d`), under its own scene; none without."""
    return _grid_runs(cfg["scene"], cfg) if (cfg := regime_three_d(section)) is not None else []


REGIME_SNAPSHOTS = 5  # field snapshots at t_end/5, 2 t_end/5, ...: the class's history


def regime_overrides(section: dict):
    """`--set` arguments of one regime run from its wildcards (scene, f_t in MPa, a, speed); its
    grid's end time, with field snapshots at fifths of it (when did the class settle?)."""
    cfg = regime_three_d(section)

    def overrides(wildcards) -> str:
        grid = cfg if cfg is not None and wildcards.scene == cfg["scene"] else section["regime"]
        t_end = grid["t_end"]
        snaps = ",".join(f"{k * t_end / REGIME_SNAPSHOTS:.6e}" for k in range(1, REGIME_SNAPSHOTS))
        return (f"--set material.f_t={wildcards.ft}e+6 "
                f"--set numerics.contact_a={wildcards.a} "
                f"--set particles.impact_velocity={wildcards.v} "
                f"--set outputs.t_end={t_end!r} "
                f"--set {shlex.quote(f'outputs.snapshot_times=[{snaps}]')} "
                f"--set particles.masses.distribution=homogeneous --set particles.precrack=none")
    return overrides


def regime_resource(section: dict, key: str):
    """Per-run resources of rule impact_regime_run: the 3D grid's for its scene."""
    cfg = regime_three_d(section)
    return _scene_value(section, key, cfg, {cfg["scene"]} if cfg is not None else set())


def strength_runs(section: dict) -> list[str]:
    """Runs of the static-strength sensitivity (``impact.strength_sweep``); none without."""
    if not (sweep := section.get("strength_sweep")):
        return []
    scene = sweep["scene"]
    return [f"results/impact/strength/{scene}/x{factor:g}/{masses}/seed{seed}.nc"
            for factor in sweep["factors"]
            for masses, seeds_ in (("homogeneous", [0]), (section["distribution"],
                                                          sweep["seeds"]))
            for seed in seeds_]


def strength_overrides(section: dict):
    """`--set` arguments of one strength-sweep run: f_t = factor x the scene's f_t."""
    from craquelure.scene import load_scene

    sweep = section["strength_sweep"]

    def overrides(wildcards) -> str:
        f_t = float(wildcards.factor) * load_scene(f"impact/{wildcards.scene}").get(
            "material.f_t")
        return (f"--set material.f_t={f_t!r} --set numerics.kappa={sweep['kappa']!r} "
                f"--set particles.masses.distribution={wildcards.masses} "
                f"--set particles.precrack=none")
    return overrides
