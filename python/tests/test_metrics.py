"""Metrics from Python: against a NumPy brute force, the C++ tool, and every layout."""

import math

import numpy as np
import pytest

import plantnbv as pn


def brute_force(reference, reconstruction, rho):
    """Nearest-neighbour distances the slow way, in double precision."""
    t = reference.astype(np.float32).astype(np.float64)
    r = reconstruction.astype(np.float32).astype(np.float64)
    d = np.sqrt(((r[:, None, :] - t[None, :, :]) ** 2).sum(axis=2))
    r_to_t, t_to_r = d.min(axis=1), d.min(axis=0)
    precision, recall = (r_to_t < rho).mean(), (t_to_r < rho).mean()
    f1 = 0.0 if precision + recall == 0 else 2 * precision * recall / (precision + recall)
    return r_to_t, t_to_r, precision, recall, f1


@pytest.fixture
def clouds():
    rng = np.random.default_rng(7)
    reference = rng.uniform(0.0, 0.05, size=(400, 3))
    reconstruction = reference[:300] + rng.normal(0.0, 0.002, size=(300, 3))
    return reference, reconstruction


def test_metrics_equal_a_numpy_brute_force(clouds):
    reference, reconstruction = clouds
    r_to_t, t_to_r, precision, recall, f1 = brute_force(reference, reconstruction, 0.003)
    m = pn.metrics(reference, reconstruction, rho=0.003)
    assert m.valid
    assert m.precision == precision and m.recall == recall
    assert m.f1 == pytest.approx(f1, rel=1e-12)
    assert m.mean_dist_reconstruction_to_reference == pytest.approx(r_to_t.mean(), rel=1e-12)
    assert m.mean_dist_reference_to_reconstruction == pytest.approx(t_to_r.mean(), rel=1e-12)
    assert m.chamfer == pytest.approx(r_to_t.mean() + t_to_r.mean(), rel=1e-12)
    assert (m.reference_points, m.reconstruction_points) == (400, 300)
    ours_r, ours_t = pn.ReconstructionMetrics(reference).distances(reconstruction)
    np.testing.assert_allclose(ours_r, r_to_t, rtol=1e-12)
    np.testing.assert_allclose(ours_t, t_to_r, rtol=1e-12)


def test_every_layout_and_dtype_gives_the_same_numbers(clouds):
    reference, reconstruction = clouds
    expected = pn.metrics(reference, reconstruction).to_dict()
    wide = np.zeros((reference.shape[0], 7))
    wide[:, 2:5] = reference
    layouts = [
        reference.astype(np.float32),
        np.asfortranarray(reference),
        np.asfortranarray(reference.astype(np.float32)),
        wide[:, 2:5],  # a non-contiguous slice
        np.ascontiguousarray(reference[::-1])[::-1],  # negative strides
        reference.tolist(),  # a nested list
    ]
    for layout in layouts:
        assert pn.metrics(layout, reconstruction).to_dict() == expected


def test_the_reference_tree_is_kept_for_many_reconstructions(clouds):
    reference, reconstruction = clouds
    evaluator = pn.ReconstructionMetrics(reference, rho=0.003)
    for n in (10, 100, 300):
        assert evaluator.compute(reconstruction[:n]).to_dict() == \
            pn.metrics(reference, reconstruction[:n]).to_dict()
    evaluator.rho = 0.001
    assert evaluator.compute(reconstruction).rho == 0.001
    with pytest.raises(ValueError, match="rho|threshold"):
        evaluator.rho = -1.0


def test_reused_distances_give_the_results_of_a_fresh_compute(clouds):
    reference, reconstruction = clouds
    evaluator = pn.ReconstructionMetrics(reference, reuse_distances=True)
    assert evaluator.reuse_distances
    # Growing, then with points left out: what a map's occupied voxels do view by view.
    for part in (reconstruction[:100], reconstruction[:250], reconstruction[50:300],
                 reconstruction[50:300], reconstruction[::2]):
        assert evaluator.compute(part).to_dict() == pn.metrics(reference, part).to_dict()
    evaluator.reuse_distances = False
    assert not evaluator.reuse_distances
    assert not pn.ReconstructionMetrics(reference).reuse_distances


def test_non_finite_points_are_ignored_and_empty_clouds_are_invalid(clouds):
    reference, reconstruction = clouds
    with_nan = np.vstack([reconstruction, [[np.nan, 0, 0], [np.inf, 1, 1]]])
    assert pn.metrics(reference, with_nan).to_dict() == pn.metrics(reference, reconstruction).to_dict()
    empty = pn.metrics(reference, np.empty((0, 3)))
    assert not empty.valid and empty.f1 == 0 and math.isinf(empty.chamfer)


def test_metrics_equal_the_tool_on_the_same_files(clouds, cli, tmp_path):
    reference, reconstruction = clouds
    pn.write_cloud(tmp_path / "t.ply", reference)
    pn.write_cloud(tmp_path / "r.pcd", reconstruction)
    tool = cli("eval", "--reference", tmp_path / "t.ply", "--reconstruction",
               tmp_path / "r.pcd", "--rho", 0.003, "--json", parse_json=True)
    ours = pn.metrics(pn.read_cloud(tmp_path / "t.ply"), pn.read_cloud(tmp_path / "r.pcd"),
                      rho=0.003).to_dict()
    for key in ("chamfer", "precision", "recall", "f1", "rho", "reference_points",
                "reconstruction_points", "mean_dist_reconstruction_to_reference",
                "mean_dist_reference_to_reconstruction", "valid"):
        assert ours[key] == tool[key], key


def test_mesh_ground_truth_equals_the_tool(placed, cli, tmp_path):
    mesh = tmp_path / "plant.ply"
    pn.write_mesh(mesh, placed.plant.mesh)
    reconstruction = pn.voxel_grid(pn.sample_mesh(placed.plant.mesh, 20000, seed=4),
                                   0.003, centres=True)
    pn.write_cloud(tmp_path / "r.ply", reconstruction)
    tool = cli("eval", "--reference", mesh, "--reconstruction", tmp_path / "r.ply",
               "--json", parse_json=True)
    reference = pn.read_geometry(mesh, resolution_m=0.003)
    ours = pn.metrics(reference, reconstruction, rho=0.003)
    assert (ours.f1, ours.chamfer, ours.reference_points) == \
        (tool["f1"], tool["chamfer"], tool["reference_points"])


def test_views_to_reach():
    assert pn.views_to_reach([0.5, 0.79, 0.8, 0.95], 0.8) == 3
    assert pn.views_to_reach([0.5, 0.6], 0.9) is None
    assert pn.views_to_reach([float("nan"), 0.9], 0.9) == 2
