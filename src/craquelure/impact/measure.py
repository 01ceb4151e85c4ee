"""Measurements of an impact run (spec section 6), from reference (grid) positions and fields.

- Cracked fraction φ_c = Σ V0 [c ≥ 0.9] / Σ V0 (equal V0: a particle count ratio), where the
  crack indicator c is, by ``material.cracked_measure``, the softening
  s = (κ − κ0)/(κ_f − κ0) clipped to [0, 1] (default) or D_t (the spec's label).
  Decision [D]: with κ_f ≈ 100 κ0, D_t = 0.9 is reached at κ ≈ 9 κ0, where the point still
  carries 92 % of f_t (nearly the whole disc after the first stress wave); s ≥ 0.9 leaves
  ≤ 0.1 f_t (an open crack), what the source's black "failed" maps show. Both fractions are
  reported (``cracked_fraction``, ``cracked_fraction_damage``).
- Main cracks: clusters of cracked, not crushed particles, adjacent if their reference distance
  is ≤ 1.5Δ; a cluster counts if its reference extent along its principal axis is ≥ R. Angle θ to
  the vertical in (−90°, 90°], length = extent along the axis + Δ.
- Crack crossings of the centre line [D]: the number of separate runs of cracked, not crushed
  particles along the grid row nearest the disc centre height. The cluster rule above merges
  radial cracks that a transverse crack or a branch joins (a fan of five is one cluster); the
  crossings count them: the source's single central main crack is 1 crossing near x = 0.
- Crushed zone [D]: crushed particles (ε̄_p ≥ 0.0035) in clusters that touch the lowest two grid
  rows (the contact region; "connected to the lowest particle" generalised to the rows that
  touch the base); area A_cr = count·Δ² (per metre), height h_cr = reference y-extent + Δ.
- Contact: peak force, impulse ∫F dt, duration (first to last sample with F > 1 % of the peak),
  rebound = final centre-of-mass v_y.
- 3D [D]: the crack and crushed-zone geometry is measured on the mid-thickness slab, the layer
  of particles nearest the disc's mid-plane z = 0 (the lower one on a tie): the section the
  source's crack maps show. The cracked fraction is over the whole body.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree


def components(n: int, pairs: np.ndarray) -> tuple[int, np.ndarray]:
    """(count, labels) of the connected components of n points joined by ``pairs`` (m, 2)."""
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    return connected_components(graph, directed=False)


def clusters(x0: np.ndarray, y0: np.ndarray, member: np.ndarray, spacing: float,
             link: float = 1.5) -> list[np.ndarray]:
    """Index arrays of the connected clusters of ``member`` particles."""
    idx = np.flatnonzero(member)
    if idx.size == 0:
        return []
    pts = np.column_stack([x0[idx], y0[idx]])
    pairs = cKDTree(pts).query_pairs(link * spacing * (1 + 1e-9), output_type="ndarray")
    n, labels = components(idx.size, pairs)
    return [idx[labels == c] for c in range(n)]


def principal_axis(x: np.ndarray, y: np.ndarray) -> tuple[float, float, float]:
    """(extent along the principal axis, angle to the vertical in degrees, extent across)."""
    if x.size < 2:
        return 0.0, 0.0, 0.0
    pts = np.column_stack([x - x.mean(), y - y.mean()])
    _, vecs = np.linalg.eigh(pts.T @ pts)
    u = vecs[:, -1]
    if u[1] < 0 or (u[1] == 0 and u[0] < 0):
        u = -u
    along = pts @ u
    across = pts @ np.array([-u[1], u[0]])
    angle = math.degrees(math.atan2(u[0], u[1]))
    return float(np.ptp(along)), angle, float(np.ptp(across))


def main_cracks(x0, y0, damage, plastic, spacing, radius, cracked=0.9, crushed=0.0035):
    """List of dicts (length, angle_deg, n) of the main cracks, longest first."""
    member = (damage >= cracked) & (plastic < crushed)
    out = []
    for c in clusters(x0, y0, member, spacing):
        extent, angle, _ = principal_axis(x0[c], y0[c])
        if extent >= radius:
            out.append({"length": extent + spacing, "angle_deg": angle, "n": int(c.size)})
    return sorted(out, key=lambda d: -d["length"])


def centre_line_crossings(x0, y0, damage, plastic, spacing, centre_y, cracked=0.9,
                          crushed=0.0035) -> tuple[int, str]:
    """(number of cracked runs along the grid row nearest y = centre_y, their mean x in mm)."""
    idx = np.flatnonzero(_centre_row(y0, centre_y, spacing))
    idx = idx[np.argsort(x0[idx])]
    hit = (damage[idx] >= cracked) & (plastic[idx] < crushed)
    runs = [float(x0[idx[run]].mean()) for run in _runs_of(hit)]
    return len(runs), ",".join(f"{1e3 * x:.0f}" for x in runs)


def crushed_zone(x0, y0, plastic, spacing, crushed=0.0035) -> tuple[float, float]:
    bottom = y0 <= y0.min() + 1.01 * spacing
    chosen = [c for c in clusters(x0, y0, plastic >= crushed, spacing) if bottom[c].any()]
    if not chosen:
        return 0.0, 0.0
    idx = np.concatenate(chosen)
    return idx.size * spacing**2, float(np.ptp(y0[idx])) + spacing


def precrack_agreement(x0, y0, damage, precrack, spacing, cracked=0.9) -> float:
    """Fraction of particles within 1.5Δ of a pre-crack particle that are cracked."""
    if not precrack.any():
        return float("nan")
    pts = np.column_stack([x0, y0])
    return float(np.mean(damage[_near(pts, pts[precrack], 1.5 * spacing)] >= cracked))


def contact_metrics(t, force, vcm_y) -> dict[str, float]:
    t, force = np.asarray(t), np.asarray(force)
    peak = float(force.max()) if force.size else 0.0
    impulse = float(np.trapezoid(force, t)) if force.size > 1 else 0.0
    on = np.flatnonzero(force > 0.01 * peak) if peak > 0 else np.array([], int)
    duration = float(t[on[-1]] - t[on[0]]) if on.size else 0.0
    return {"contact_force_peak": peak, "contact_impulse": impulse,
            "contact_duration": duration, "rebound_velocity": float(vcm_y[-1])}


def mid_slab(z0: np.ndarray, spacing: float) -> np.ndarray:
    """Mask of the layer nearest the mid-plane z = 0 (the lower one on a tie)."""
    near = np.abs(z0) <= np.abs(z0).min() + 0.01 * spacing
    if (near & (z0 < 0)).any():
        near &= z0 < 0
    return near


def run_metrics(x0, y0, damage, plastic, precrack, spacing, radius, cracked=0.9,
                crushed=0.0035, centre_y=None, z0=None) -> dict[str, float]:
    """The run's measurements (module docstring); ``z0``: on the 3D mid-thickness slab."""
    fraction = float(np.mean(damage >= cracked))
    if z0 is not None:
        slab = mid_slab(np.asarray(z0), spacing)
        x0, y0, damage, plastic, precrack = (np.asarray(a)[slab] for a in
                                             (x0, y0, damage, plastic, precrack))
    mcs = main_cracks(x0, y0, damage, plastic, spacing, radius, cracked, crushed)
    if centre_y is None:
        centre_y = 0.5 * (y0.min() + y0.max())
    n_cross, x_cross = centre_line_crossings(x0, y0, damage, plastic, spacing, centre_y,
                                             cracked, crushed)
    area, height = crushed_zone(x0, y0, plastic, spacing, crushed)
    out = {
        "cracked_fraction": fraction, "n_main_cracks": len(mcs),
        "main_crack_angle_deg": mcs[0]["angle_deg"] if mcs else float("nan"),
        "main_crack_length": mcs[0]["length"] if mcs else 0.0,
        "main_crack_angles_deg": ",".join(f"{m['angle_deg']:.1f}" for m in mcs),
        "crushed_area": area, "crushed_height": height,
        "centre_crossings": n_cross, "centre_crossings_x_mm": x_cross,
    }
    if precrack.any():
        out["precrack_cracked_fraction"] = precrack_agreement(x0, y0, damage, precrack, spacing,
                                                              cracked)
        _, angle, _ = principal_axis(x0[precrack], y0[precrack])
        out["precrack_angle_deg"] = angle
        out.update(precrack_following(x0, y0, damage, plastic, precrack, spacing, centre_y,
                                      cracked, crushed))
    out.update(revised_cracks(x0, y0, damage, plastic, spacing, centre_y, cracked, crushed))
    return out


# --- check 12 (spec section 10) -------------------------------------------------------------
# "Main crack" [D]: a cracked, not crushed cluster that starts at the contact zone (the crushed
# zone plus the two lowest grid rows; a particle within 1.5 Delta of it) and reaches 0.5 D
# towards the far rim by its own vertical extent (a crack on a tall crushed zone does not reach
# far). A cluster that branches above the contact counts one main crack per cracked run along
# the centre row (as in centre_line_crossings).

def _near(points_a, points_b, radius) -> np.ndarray:
    """Mask over points_a: within ``radius`` of any of points_b."""
    if len(points_b) == 0:
        return np.zeros(len(points_a), bool)
    d, _ = cKDTree(points_b).query(points_a)
    return d <= radius * (1 + 1e-9)


def _centre_row(y0, centre_y, spacing):
    row = np.abs(y0 - centre_y) <= np.abs(y0 - centre_y).min() + 0.01 * spacing
    return row & (y0 <= centre_y + 0.01 * spacing)  # one row when the centre is between two


def _runs(xs: np.ndarray, spacing: float) -> list[float]:
    """Mean x of the runs of consecutive grid positions in the sorted ``xs``."""
    if xs.size == 0:
        return []
    xs = np.sort(xs)
    breaks = np.flatnonzero(np.diff(xs) > 1.5 * spacing) + 1
    return [float(r.mean()) for r in np.split(xs, breaks)]


def contact_zone(x0, y0, crushed, spacing) -> np.ndarray:
    """Points of the contact zone: the two lowest rows and the crushed clusters on them."""
    bottom = y0 <= y0.min() + 1.01 * spacing
    zone = bottom.copy()
    for c in clusters(x0, y0, crushed, spacing):
        if bottom[c].any():
            zone[c] = True
    return np.column_stack([x0[zone], y0[zone]])


def revised_cracks(x0, y0, crack, plastic, spacing, centre_y, cracked=0.9,
                   crushed=0.0035) -> dict:
    """Per-run quantities of the revised check 12 (main cracks from the contact zone)."""
    diameter = float(np.ptp(y0)) + spacing
    member = (crack >= cracked) & (plastic < crushed)
    zone_pts = contact_zone(x0, y0, plastic >= crushed, spacing)
    row = _centre_row(y0, centre_y, spacing)
    mains, others = [], []
    for c in clusters(x0, y0, member, spacing):
        extent, angle, _ = principal_axis(x0[c], y0[c])
        reach = float(np.ptp(y0[c])) + spacing
        starts = bool(_near(np.column_stack([x0[c], y0[c]]), zone_pts, 1.5 * spacing).any())
        info = {"idx": c, "length": extent + spacing, "angle": angle, "reach": reach,
                "crossings": _runs(x0[c][row[c]], spacing)}
        (mains if starts and reach >= 0.5 * diameter else others).append(info)
    mains.sort(key=lambda d: -d["length"])
    crossings = [x for m in mains for x in (m["crossings"] or [float("nan")])]
    out = {"n_main_cracks_revised": len(crossings),
           "main_crossings_x_mm": ",".join(f"{1e3 * x:.0f}" for x in crossings),
           "n_secondary_cracks": sum(o["length"] > 2 * spacing for o in others)}
    if mains:
        main = mains[0]
        central = min(main["crossings"], key=abs) if main["crossings"] else float("nan")
        rest = [o["length"] for o in others] + [m["length"] for m in mains[1:]]
        near = _near(np.column_stack([x0, y0]),
                     np.column_stack([x0[main["idx"]], y0[main["idx"]]]), 3 * spacing)
        out.update({"main_crack_length_revised": main["length"],
                    "main_crack_theta_deg": main["angle"], "main_crack_x_mid": central,
                    "second_crack_length": max(rest) if rest else 0.0,
                    "cracked_fraction_near_main": float(np.mean(crack[near] >= cracked))})
    else:
        out.update({"main_crack_length_revised": 0.0, "main_crack_theta_deg": float("nan"),
                    "main_crack_x_mid": float("nan"),
                    "second_crack_length": max((o["length"] for o in others), default=0.0),
                    "cracked_fraction_near_main": float("nan")})
    return out


def line_frame(x0, y0, precrack):
    """A zero-mass line's frame: its centre and direction u (the pre-crack particles' mean and
    principal axis), every particle's coordinates along and across it, and the line's extent along
    it."""
    px, py = x0[precrack], y0[precrack]
    cx, cy = px.mean(), py.mean()
    _, angle, _ = principal_axis(px, py)
    u = np.array([math.sin(math.radians(angle)), math.cos(math.radians(angle))])
    rel = np.column_stack([x0 - cx, y0 - cy])
    along, across = rel @ u, rel @ np.array([-u[1], u[0]])
    return ((cx, cy), u, along, across, float(along[precrack].min()), float(along[precrack].max()))


def _line_x(cx, cy, u, centre_y) -> float:
    """x where the line through (cx, cy) along u crosses the height centre_y."""
    return cx + (centre_y - cy) * (u[0] / u[1]) if abs(u[1]) > 1e-9 else cx


def precrack_following(x0, y0, crack, plastic, precrack, spacing, centre_y, cracked=0.9,
                       crushed=0.0035) -> dict:
    """Does the crack follow a zero-mass line (the pre-crack particles' principal axis between their
    extreme projections)? Coverage: fraction of the line's length (sampled every Delta/2) with a
    cracked, not pre-crack particle within Delta of it and Delta/2 along it. Tips: how far the
    cracked clusters touching the line extend beyond each end. Elsewhere: main cracks crossing the
    centre row more than 3 Delta from the line."""
    (cx, cy), u, along, across, s_lo, s_hi = line_frame(x0, y0, precrack)
    hit = (crack >= cracked) & (plastic < crushed) & ~precrack
    close = hit & (np.abs(across) <= spacing * (1 + 1e-9))
    covered = [bool(np.any(close & (np.abs(along - s) <= 0.5 * spacing * (1 + 1e-9))))
               for s in np.arange(s_lo, s_hi + 1e-12, 0.5 * spacing)]
    beyond_lo = beyond_hi = 0.0
    for c in clusters(x0, y0, hit, spacing):
        if close[c].any():
            beyond_hi = max(beyond_hi, float(along[c].max()) - s_hi)
            beyond_lo = max(beyond_lo, s_lo - float(along[c].min()))
    rc = revised_cracks(x0, y0, crack, plastic, spacing, centre_y, cracked, crushed)
    line_x = _line_x(cx, cy, u, centre_y)
    xs = [float(v) * 1e-3 for v in rc["main_crossings_x_mm"].split(",") if v]
    elsewhere = sum(abs(x - line_x) > 3 * spacing for x in xs)
    return {"precrack_coverage": float(np.mean(covered)) if covered else float("nan"),
            "precrack_tip_extension_low": max(beyond_lo, 0.0),
            "precrack_tip_extension_high": max(beyond_hi, 0.0),
            "main_cracks_elsewhere": int(elsewhere)}


# --- cracks measured by their opening (spec section 6) -------------------------------------
# A crack is what opened. Neighbour pairs of the plane (2D) or the mid-thickness layer (3D):
# massive particles at reference distance <= 1.5 Delta, plus "bridges" across a zero-mass
# particle (massive i, j at <= 2.5 Delta whose midpoint lies within 0.6 Delta of a zero-mass
# particle, a passive tracer). A pair's opening is w = |x_j - x_i| - |X_j - X_i| (0 for rigid
# motions; the normal opening for the pair normal to a crack); it is opened if w > w_c =
# 2 G_F / f_t, the crack band's full-softening opening l_c eps_f (a stress-free crack). Crushed
# pairs count like any other. A crack is a connected set of opened pairs (midpoints within
# 1.5 Delta). Along the centre row a run of k opened gaps is ceil(k/2) cracks: the band softens
# two columns (:mod:`.effects.damage`), so one crack may open two adjacent gaps. A main crack
# starts at the contact zone (the crushed zone and the two lowest rows, within 1.5 Delta of its
# pairs) and reaches at least 0.5 D towards the far rim (vertical extent of its pair midpoints
# + Delta); N_main counts the centre-row cracks of main cracks.

def neighbour_pairs(x0, y0, mass, spacing) -> np.ndarray:
    """(n, 2) index pairs of the opening measure (module comment above)."""
    pts = np.column_stack([x0, y0])
    massive = mass > 0
    tree = cKDTree(pts)
    pairs = tree.query_pairs(1.5 * spacing * (1 + 1e-9), output_type="ndarray")
    if len(pairs):
        pairs = pairs[massive[pairs[:, 0]] & massive[pairs[:, 1]]]
    if (~massive).any() and massive.any():
        far = tree.query_pairs(2.5 * spacing * (1 + 1e-9), output_type="ndarray")
        far = far[massive[far[:, 0]] & massive[far[:, 1]]]
        mid = 0.5 * (pts[far[:, 0]] + pts[far[:, 1]])
        d, _ = cKDTree(pts[~massive]).query(mid)
        bridges = far[(d <= 0.6 * spacing) & (np.hypot(*(pts[far[:, 1]] - pts[far[:, 0]]).T)
                                              > 1.5 * spacing * (1 + 1e-9))]
        pairs = np.concatenate([pairs.reshape(-1, 2), bridges]) if len(bridges) else pairs
    return np.asarray(pairs, int).reshape(-1, 2)


def pair_openings(pairs, x0, y0, x, y) -> np.ndarray:
    """w = |x_j - x_i| - |X_j - X_i| per pair."""
    i, j = pairs[:, 0], pairs[:, 1]
    return (np.hypot(x[j] - x[i], y[j] - y[i]) - np.hypot(x0[j] - x0[i], y0[j] - y0[i]))


def full_softening_opening(G_F: float, f_t: float) -> float:
    """w_c = 2 G_F / f_t: the crack band's opening at full softening (l_c eps_f)."""
    return 2.0 * G_F / f_t


def _row_gaps(x0, y0, x, y, mass, spacing, centre_y):
    """Consecutive massive particles of the centre row (sorted by X): (index pairs, X of the
    gap midpoints, openings) — the row's horizontal gaps; a zero-mass particle is bridged."""
    idx = np.flatnonzero(_centre_row(y0, centre_y, spacing) & (mass > 0))
    idx = idx[np.argsort(x0[idx])]
    if idx.size < 2:
        return np.zeros((0, 2), int), np.zeros(0), np.zeros(0)
    pairs = np.column_stack([idx[:-1], idx[1:]])
    close = (x0[pairs[:, 1]] - x0[pairs[:, 0]]) <= 2.5 * spacing * (1 + 1e-9)
    pairs = pairs[close]
    return (pairs, 0.5 * (x0[pairs[:, 0]] + x0[pairs[:, 1]]), pair_openings(pairs, x0, y0, x, y))


def _runs_of(flags: np.ndarray) -> list[np.ndarray]:
    """Index arrays of the runs of consecutive True in ``flags``."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], np.asarray(flags, np.int8), [0]])))
    return [np.arange(a, b) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def opening_cracks(x0, y0, x, y, mass, plastic, spacing, w_c, centre_y=None,
                   crushed=0.0035, precrack=None) -> dict:
    """Cracks by opening (module comment above) of one plane/layer: per crack its centre-row
    crossings, angle, length, largest opening and whether it is a main crack; N_main, the centre
    row's opened runs, the share of the row's opening the largest run carries, and with ``precrack``
    (mask of the zero-mass line) the line's coverage and whether the largest opening lies on it."""
    x0, y0, x, y = (np.asarray(a, float) for a in (x0, y0, x, y))
    mass, plastic = np.asarray(mass, float), np.asarray(plastic, float)
    if centre_y is None:
        centre_y = 0.5 * (y0.min() + y0.max())
    diameter = float(np.ptp(y0)) + spacing
    pairs = neighbour_pairs(x0, y0, mass, spacing)
    w = pair_openings(pairs, x0, y0, x, y)
    opened = w > w_c
    pts = np.column_stack([x0, y0])
    mid = 0.5 * (pts[pairs[:, 0]] + pts[pairs[:, 1]])
    zone_pts = contact_zone(x0, y0, plastic >= crushed, spacing)
    # centre row gaps and their runs
    gpairs, gx, gw = _row_gaps(x0, y0, x, y, mass, spacing, centre_y)
    runs = _runs_of(gw > w_c)
    total_row = float(np.clip(gw, 0.0, None).sum())
    cracks = []
    oidx = np.flatnonzero(opened)
    if oidx.size:
        for c in clusters(mid[oidx, 0], mid[oidx, 1], np.ones(oidx.size, bool), spacing):
            k = oidx[c]
            px, py = mid[k, 0], mid[k, 1]
            extent, angle, _ = principal_axis(px, py)
            reach = float(np.ptp(py)) + spacing
            starts = bool(_near(np.column_stack([px, py]), zone_pts, 1.5 * spacing).any())
            ends = set(pairs[k].ravel().tolist())
            crossing = [r for r in runs if any(int(a) in ends and int(b) in ends
                                               for a, b in gpairs[r])]
            cracks.append({"length": extent + spacing, "angle_deg": angle, "reach": reach,
                           "max_opening": float(w[k].max()), "n_pairs": int(k.size),
                           "main": starts and reach >= 0.5 * diameter, "runs": crossing,
                           "pairs": k})
    cracks.sort(key=lambda c: -c["length"])
    # a run of k opened gaps is ceil(k/2) cracks
    run_info = [{"x_mm": 1e3 * float(gx[r].mean()), "opening": float(gw[r].sum()),
                 "gaps": int(r.size), "cracks": math.ceil(r.size / 2)} for r in runs]
    main_runs = [r for c in cracks if c["main"] for r in c["runs"]]
    main_ids = {id(r) for r in main_runs}
    n_main = sum(math.ceil(r.size / 2) for r in runs if id(r) in main_ids)
    largest = max((float(gw[r].sum()) for r in runs), default=0.0)
    main = next((c for c in cracks if c["main"]), None)
    main_run = max(main_runs, key=lambda r: float(gw[r].sum()), default=None)
    out = {
        "opening_w_c": float(w_c), "n_main_cracks_opening": int(n_main),
        "n_cracks_opening": len(cracks),
        "n_secondary_cracks_opening": sum(1 for c in cracks if not c["main"]
                                          and c["length"] > 2 * spacing),
        "row_runs_x_mm": ",".join(f"{r['x_mm']:.0f}" for r in run_info),
        "row_runs_opening_mm": ",".join(f"{1e3 * r['opening']:.3f}" for r in run_info),
        "row_runs_cracks": ",".join(str(r["cracks"]) for r in run_info),
        "row_opening_total": total_row,
        "row_largest_run_share": largest / total_row if total_row > 0 else float("nan"),
        "main_run_x_mid": float(gx[main_run].mean()) if main_run is not None else float("nan"),
        "main_run_opening": float(gw[main_run].sum()) if main_run is not None else 0.0,
        "main_run_share": (float(gw[main_run].sum()) / total_row
                           if main_run is not None and total_row > 0 else float("nan")),
        "main_crack_theta_opening_deg": main["angle_deg"] if main else float("nan"),
        "main_crack_length_opening": main["length"] if main else 0.0,
        "main_crack_max_opening": main["max_opening"] if main else 0.0,
        "second_crack_length_opening": max((c["length"] for c in cracks if c is not main),
                                           default=0.0),
        "max_opening": float(w.max()) if len(w) else 0.0,
    }
    if precrack is not None and np.asarray(precrack).any():
        line = np.asarray(precrack, bool)
        out.update(_line_opening(x0, y0, pairs, w, w_c, line, spacing))
        (cx, cy), u, *_ = line_frame(x0, y0, line)
        line_x = _line_x(cx, cy, u, centre_y)
        out["main_cracks_elsewhere_opening"] = sum(
            math.ceil(r.size / 2) for r in runs
            if id(r) in main_ids and abs(float(gx[r].mean()) - line_x) > 3 * spacing)
    out["_cracks"] = cracks
    return out


def _line_opening(x0, y0, pairs, w, w_c, precrack, spacing) -> dict:
    """Coverage of a zero-mass line by opened pairs across it (a sample every Delta, covered by an
    opened pair crossing the line within Delta/2 along it), and whether the layer's largest opening
    is one of the line's pairs."""
    (cx, cy), u, along, across, s_lo, s_hi = line_frame(x0, y0, precrack)
    ai, aj = across[pairs[:, 0]], across[pairs[:, 1]]
    s_mid = 0.5 * (along[pairs[:, 0]] + along[pairs[:, 1]])
    crossing = (np.sign(ai) != np.sign(aj)) & (np.minimum(np.abs(ai), np.abs(aj))
                                               <= 1.5 * spacing)
    opened = crossing & (w > w_c)
    covered = [bool(np.any(opened & (np.abs(s_mid - s) <= 0.5 * spacing * (1 + 1e-9))))
               for s in np.arange(s_lo, s_hi + 1e-12, spacing)]
    on_line = bool(crossing[np.argmax(w)]) if len(w) else False
    return {"precrack_coverage_opening": float(np.mean(covered)) if covered else float("nan"),
            "precrack_largest_opening_on_line": on_line,
            "precrack_line_max_opening": float(w[crossing].max()) if crossing.any() else 0.0}


def row_opening_near(x0, y0, x, y, mass, spacing, centre_y, x_mid, half_width=None) -> float:
    """Summed opening of the centre row's gaps within ``half_width`` (default 2 Delta) of
    ``x_mid``: a crack's opening at another instant, from that instant's positions."""
    half = 2.0 * spacing if half_width is None else half_width
    _, gx, gw = _row_gaps(np.asarray(x0), np.asarray(y0), np.asarray(x), np.asarray(y),
                          np.asarray(mass), spacing, centre_y)
    near = np.abs(gx - x_mid) <= half * (1 + 1e-9)
    return float(np.clip(gw[near], 0.0, None).sum())


def opening_metrics(x0, y0, x, y, mass, plastic, precrack, spacing, w_c, centre_y, z0=None,
                    half=None) -> dict:
    """The opening measure (:func:`opening_cracks`) on the plane or mid-thickness layer (``z0``);
    ``half`` = (x, y) of an earlier snapshot gives ``main_run_opening_half`` and
    ``main_run_opening_growth`` = opening now / opening then, from the same gaps."""
    arrays = [np.asarray(a) for a in (x0, y0, x, y, mass, plastic, precrack, *(half or ()))]
    if z0 is not None:
        slab = mid_slab(np.asarray(z0), spacing)
        arrays = [a[slab] for a in arrays]
    x0, y0, x, y, mass, plastic, precrack, *then = arrays
    out = opening_cracks(x0, y0, x, y, mass, plastic, spacing, w_c, centre_y,
                         precrack=precrack.astype(bool) if precrack.any() else None)
    out.pop("_cracks")
    if half is not None and math.isfinite(out["main_run_x_mid"]):
        then = row_opening_near(x0, y0, *then, mass, spacing, centre_y, out["main_run_x_mid"])
        now = row_opening_near(x0, y0, x, y, mass, spacing, centre_y, out["main_run_x_mid"])
        out["main_run_opening_half"] = then
        out["main_run_opening_growth"] = now / then if then > 0 else float("inf")
    else:
        out.update(main_run_opening_half=float("nan"), main_run_opening_growth=float("nan"))
    return out
