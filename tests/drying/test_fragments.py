"""Periodic fragment labelling (drying spec section 9; section 13, check 13) and the per-run
fragment dataset / `craquelure fragments` command."""

import numpy as np
import pytest
from skimage.measure import label as sk_label

from craquelure.cli import main as cli_main
from craquelure.drying.fragments import analyse_run, fragment_areas, label_periodic
from craquelure.errors import SceneError
from craquelure.io import open_dataset, write_dataset
from craquelure.scene import load_scene_text

from .synthetic_run import lattice_run

M = 40  # synthetic image side (pixels)
DX = 0.25  # pixel spacing, so L = 10
L = M * DX


def areas(image):
    return np.sort(fragment_areas(image, DX))


# --- check 13 -----------------------------------------------------------------------------

def test_all_ones_is_one_fragment_of_area_l2():
    a = areas(np.ones((M, M), bool))
    assert a.tolist() == [pytest.approx(L * L)]


def test_one_crack_row_leaves_one_fragment():
    image = np.ones((M, M), bool)
    image[7, :] = False
    assert areas(image).tolist() == [pytest.approx((M - 1) * M * DX * DX)]


def test_row_and_column_leave_one_fragment():
    image = np.ones((M, M), bool)
    image[7, :] = False
    image[:, 30] = False
    assert areas(image).tolist() == [pytest.approx((M - 1) ** 2 * DX * DX)]


def test_two_rows_give_two_with_expected_areas():
    image = np.ones((M, M), bool)
    image[5, :] = False
    image[20, :] = False  # strips of 14 rows (6..19) and 24 rows (21..39, 0..4)
    assert areas(image) == pytest.approx(np.array([14, 24]) * M * DX * DX)


def test_two_rows_two_columns_give_four():
    image = np.ones((M, M), bool)
    image[[5, 20], :] = False
    image[:, [10, 35]] = False  # column strips of 24 (11..34) and 14 (36..39, 0..9)
    expected = np.sort(np.outer([14, 24], [24, 14]).ravel()) * DX * DX
    assert areas(image) == pytest.approx(expected)


def test_blob_cut_by_both_edges_counts_once():
    """A disc centred on the corner is four pieces for plain labelling, one on the torus."""
    j, i = np.mgrid[0:M, 0:M]
    dj = np.minimum(j, M - j)
    di = np.minimum(i, M - i)
    image = di**2 + dj**2 <= 8**2
    assert sk_label(image, connectivity=1).max() == 4
    labels, n = label_periodic(image)
    assert n == 1
    assert fragment_areas(image, DX)[0] == pytest.approx(image.sum() * DX * DX)
    # The pixel count approximates the disc area pi R^2 within the boundary pixels.
    assert image.sum() == pytest.approx(np.pi * 64, abs=2 * np.pi * 8)


def test_blob_wrapping_across_one_edge():
    j, i = np.mgrid[0:M, 0:M]
    di = np.minimum(i, M - i)  # centre on the x = 0 | L edge
    image = (di**2 + (j - 20) ** 2 <= 6**2) | ((i - 20) ** 2 + (j - 5) ** 2 <= 3**2)
    assert sk_label(image, connectivity=1).max() == 3
    labels, n = label_periodic(image)
    assert n == 2
    sizes = np.bincount(labels.ravel())[1:]
    wrapped = (di**2 + (j - 20) ** 2 <= 6**2).sum()
    assert sorted(sizes.tolist()) == sorted([wrapped, image.sum() - wrapped])


def test_blocks_touching_at_a_corner_are_two():
    image = np.zeros((M, M), bool)
    image[10:15, 10:15] = True
    image[15:20, 15:20] = True
    assert label_periodic(image)[1] == 2
    # ... also when they touch diagonally across the periodic corner.
    image = np.zeros((M, M), bool)
    image[0:3, 0:3] = True
    image[M - 3:, M - 3:] = True
    assert label_periodic(image)[1] == 2


def test_empty_image_has_no_fragment():
    assert label_periodic(np.zeros((M, M), bool))[1] == 0
    assert fragment_areas(np.zeros((M, M), bool), DX).size == 0


# --- periodic Voronoi-like tessellation ---------------------------------------------------

def test_periodic_voronoi_tessellation():
    """Cells of a periodic Voronoi tessellation separated by one-pixel cracks: one fragment per
    cell, each with exactly its cell's paste pixels (cells cut by the edges count once)."""
    size, n_cells = 160, 14
    rng = np.random.default_rng(7)
    seeds = []
    while len(seeds) < n_cells:  # well separated seeds, so no cell is thinner than a crack
        p = rng.uniform(0, size, 2)
        d = [np.abs((p - q + size / 2) % size - size / 2) for q in seeds]
        if all(np.hypot(*dd) > 30 for dd in d):
            seeds.append(p)
    seeds = np.array(seeds)
    j, i = np.mgrid[0:size, 0:size]
    dx = (i[..., None] + 0.5 - seeds[:, 0] + size / 2) % size - size / 2
    dy = (j[..., None] + 0.5 - seeds[:, 1] + size / 2) % size - size / 2
    owner = np.argmin(dx**2 + dy**2, axis=-1)
    crack = (owner != np.roll(owner, -1, axis=1)) | (owner != np.roll(owner, -1, axis=0))
    image = ~crack
    labels, n = label_periodic(image)
    assert n == n_cells
    assert sk_label(image, connectivity=1).max() > n_cells  # some cells do wrap
    for k in range(1, n + 1):
        owners = np.unique(owner[labels == k])
        assert owners.size == 1  # a fragment is one cell ...
        assert (labels == k).sum() == np.sum(image & (owner == owners[0]))  # ... all of it


# --- per-run dataset and command ----------------------------------------------------------

BANDS = ((), [("y", 0.5, 0.8)], [("y", 1.4, 1.7)], [("x", 0.2, 0.5), ("x", 1.1, 1.4)])


@pytest.fixture(scope="module")
def run():
    return lattice_run(40, 2.0, bands_per_time=BANDS, times=[2.0, 4.0, 6.0, 8.0], seed=5)


def test_analyse_run_counts_fragments_over_time(run):
    ds = analyse_run(run, phi0=0.8, spacing_h=0.05, progress=False)
    assert ds["n_fragments"].values.tolist() == [1, 1, 2, 4]
    assert ds.sizes["fragment"] == 8
    # Ragged storage: fragment_time / fragment_time_index agree with the per-time counts.
    counts = np.bincount(ds["fragment_time_index"].values, minlength=4)
    assert counts.tolist() == ds["n_fragments"].values.tolist()
    assert np.all(ds["fragment_time"].values == ds["time"].values[ds["fragment_time_index"]])
    # Intact snapshot: one fragment = the whole box.
    assert ds["fragment_area"].values[0] == pytest.approx(4.0)
    for k in range(4):
        sel = ds["fragment_time_index"].values == k
        assert ds["mean_area"].values[k] == pytest.approx(ds["fragment_area"].values[sel].mean())
        # Paste area = sum of fragment areas.
        assert ds["paste_fraction"].values[k] * 4.0 == pytest.approx(
            ds["fragment_area"].values[sel].sum())
    assert ds.attrs["first_removal_time"] == pytest.approx(run["step_time"].values[
        np.argmax(run["n_removed"].values > 0)])
    assert ds.attrs["edge_depth"] == pytest.approx(0.199 * 0.2, abs=1e-4)


def test_defaults_come_from_the_scene(run):
    ds = analyse_run(run.isel(time=[0]), progress=False)
    assert ds.attrs["phi0"] == 0.8
    assert ds.attrs["mesh_spacing_h"] == 0.01  # schema default of outputs.binarisation_spacing
    assert ds.attrs["mesh_points_per_side"] == 1000


def test_fragments_command_writes_dataset_with_provenance(run, tmp_path):
    src = run.copy()
    src.attrs["git_commit"] = "abc123"
    write_dataset(src, tmp_path / "run.nc")
    out = tmp_path / "frag.nc"
    rc = cli_main(["fragments", str(tmp_path / "run.nc"), "--out", str(out), "--phi0", "0.8",
                   "--spacing", "0.05"])
    assert rc == 0
    ds = open_dataset(out)
    assert ds["n_fragments"].values.tolist() == [1, 1, 2, 4]
    assert ds.attrs["run_git_commit"] == "abc123"
    assert ds.attrs["seed"] == 5
    assert "drying" in ds.attrs["scene"] and "git_commit" in ds.attrs
    assert ds.attrs["effects"] == run.attrs["effects"]


def test_fragments_command_rejects_bad_input(tmp_path):
    assert cli_main(["fragments", str(tmp_path / "none.nc"), "--out", "x.nc"]) == 2
    bad = lattice_run(40, 2.0).drop_vars("alive")
    write_dataset(bad, tmp_path / "bad.nc")
    assert cli_main(["fragments", str(tmp_path / "bad.nc"), "--out",
                     str(tmp_path / "o.nc")]) == 2
    assert not (tmp_path / "o.nc").exists()


def test_labels_numbered_in_raster_order_of_first_pixel():
    rng = np.random.default_rng(2)
    image = rng.random((120, 120)) > 0.45  # near the percolation threshold: many clusters
    labels, n = label_periodic(image)
    assert n > 10
    values, first = np.unique(labels.ravel(), return_index=True)
    assert values.tolist() == list(range(n + 1))
    assert np.all(np.diff(first[1:]) > 0)


def test_archived_run_with_an_older_scene_key_stays_analysable(run):
    """A dataset's scene is read back as written: a key today's schema no longer knows (as
    after a rename) must not make the archived run unreadable, and the analysis is unchanged."""
    old = run.copy()
    old.attrs = {**run.attrs, "scene": run.attrs["scene"].replace(
        "material:\n", "material:\n  retired_key_from_an_older_schema: 1.0\n", 1)}
    with pytest.raises(SceneError, match="retired_key_from_an_older_schema"):
        load_scene_text(old.attrs["scene"])  # today's schema rejects it ...
    a = analyse_run(old, phi0=0.8, spacing_h=0.05, progress=False)  # ... the analysis does not
    b = analyse_run(run, phi0=0.8, spacing_h=0.05, progress=False)
    assert a["n_fragments"].values.tolist() == b["n_fragments"].values.tolist() == [1, 1, 2, 4]
    assert np.array_equal(a["fragment_area"].values, b["fragment_area"].values)
