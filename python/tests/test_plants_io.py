"""Plants, the simulated camera, filters and files, from Python."""

import numpy as np
import pytest

import plantnbv as pn

from conftest import V0


def test_generated_plants_are_reproducible_and_labelled():
    a, b = pn.generate_plant(seed=5, growth_stage=0.2), pn.generate_plant(seed=5, growth_stage=0.2)
    np.testing.assert_array_equal(a.mesh.vertices, b.mesh.vertices)
    mesh = a.mesh
    assert mesh.vertices.dtype == np.float32 and mesh.triangles.shape == (len(mesh), 3)
    assert set(np.unique(mesh.labels)) <= set(pn.PART_LABELS.values())
    assert pn.PART_LABELS["stem"] in mesh.labels and "stem" in mesh.node_names
    assert pn.default_plant(3).anatomy_json() == pn.place_plant(seed=3, base=[0, 0, 0]).plant.anatomy_json()
    simplified = pn.generate_plant(seed=5, growth_stage=0.2, simplified=True)
    assert len(simplified.mesh) < len(mesh)


def test_anatomy_rois_and_placement(placed):
    plant = placed.plant
    anatomy = plant.anatomy
    assert anatomy["stem"]["axis"].shape[1] == 3
    assert len(anatomy["leaves"]) == plant.leaf_node_count
    node = anatomy["leaves"][0]["node"]["position"]
    assert node.shape == (3,)
    np.testing.assert_allclose(plant.base_position, [1.0, 0.0, 0.8])
    rois = placed.rois
    assert set(rois) == {"whole_plant", "main_stem", "leaf_nodes", "fruit"}
    assert len(rois["leaf_nodes"]) == 3 and rois["main_stem"].boxes[0].name == "main_stem"
    np.testing.assert_allclose(rois["main_stem"].boxes[0].size, [0.05, 0.05, 0.7])
    assert plant.roi("leaf_nodes").boxes[0].center.tolist() == rois["leaf_nodes"].boxes[0].center.tolist()
    assert len(plant.leaf_node_roi([0, 1])) == 2
    mine = pn.generate_plant(seed=1)
    mine.place([2.0, 1.0, 0.5], yaw_deg=90)
    np.testing.assert_allclose(mine.base_position, [2.0, 1.0, 0.5])
    assert mine.yaw_rad == pytest.approx(np.pi / 2)
    lo, hi = mine.mesh.bounds()
    assert lo[2] >= 0.5 - 1e-6 and mine.mesh.area() > 0.01


def test_the_camera_sees_the_plant_where_its_depth_says(sensor, camera, placed):
    frame = sensor.capture(T_W_C=V0)
    depth, points, labels = frame["depth"], frame["points"], frame["labels"]
    assert depth.shape == (240, 320) and points.shape == (240, 320, 3)
    hit = np.isfinite(depth)
    assert 0.1 < hit.mean() < 1.0
    np.testing.assert_allclose(pn.depth_to_points(depth, camera, frame["T_W_O"])[hit],
                               points[hit], atol=1e-5)
    assert (labels[~hit] == 0).all()
    plant_pixels = np.isin(labels, [pn.PART_LABELS[k] for k in ("stem", "leaflet", "petiole")])
    assert plant_pixels.sum() > 1000
    again = sensor.capture(T_W_O=frame["T_W_O"])
    np.testing.assert_array_equal(again["depth"], depth)


def test_scans_and_meshes_become_plants(placed, tmp_path):
    points = pn.sample_mesh(placed.plant.mesh, 20000, seed=2)
    scan = pn.plant_from_scan(points, name="my_scan")
    assert scan.scan_points.shape == (20000, 3) and len(scan.mesh) == 0
    sensor = pn.SimulatedDepthSensor(pn.CameraIntrinsics.l515("320x240"))
    scan.place()
    sensor.set_plant(scan)
    assert np.isfinite(sensor.capture(T_W_C=V0)["depth"]).any()
    pn.write_mesh(tmp_path / "p.ply", placed.plant.mesh)
    model = pn.place_plant(model=str(tmp_path / "p.ply"))
    # A labelled model: its bounding box, and a box per connected group of fruit triangles.
    assert set(model.rois) == {"whole_plant", "fruit"} and model.warnings == []
    assert len(model.rois["fruit"].boxes) >= len(placed.rois["fruit"].boxes)
    with pytest.warns(UserWarning, match="label rule stem=no_such_node matches no triangle"):
        labelled = pn.place_plant(model=str(tmp_path / "p.ply"), labels="stem=no_such_node")
    assert len(labelled.warnings) == 1
    # A plant split into two files, as --model repeated: one mesh of both.
    pn.write_mesh(tmp_path / "q.ply", placed.plant.mesh)
    split = pn.place_plant(model=[str(tmp_path / "p.ply"), str(tmp_path / "q.ply")])
    assert len(split.plant.mesh) == 2 * len(placed.plant.mesh)
    assert "and 1 more file" in split.description
    # A y-up file (Blender's OBJ), 1 m along y in centimetres: up_axis stands it up.
    (tmp_path / "y_up.obj").write_text("v 0 0 0\nv 0 100 0\nv 0 0 10\nf 1 2 3\n")
    upright = pn.place_plant(model=str(tmp_path / "y_up.obj"), scale=0.01, up_axis="y")
    assert upright.plant.anatomy["stem"]["top_height_m"] == pytest.approx(1.0, abs=1e-6)
    with pytest.raises(ValueError, match="up axis: expected 'file', 'y' or 'z', got 'Y_UP'"):
        pn.place_plant(model=str(tmp_path / "y_up.obj"), up_axis="Y_UP")
    mesh_plant = pn.plant_from_mesh(pn.read_mesh(tmp_path / "p.ply"), name="m")
    assert mesh_plant.name == "m" and len(mesh_plant.mesh) == len(placed.plant.mesh)


def test_filters_and_sampling():
    points, labels = pn.sample_mesh(pn.generate_plant(seed=0).mesh, 50000, seed=3,
                                    return_labels=True)
    assert points.shape == (50000, 3) and labels.shape == (50000,)
    again = pn.sample_mesh(pn.generate_plant(seed=0).mesh, 50000, seed=3)
    np.testing.assert_array_equal(points, again)
    centres, voxel_labels = pn.voxel_grid(points, 0.005, centres=True, labels=labels)
    assert len(centres) == len(voxel_labels) < len(points)
    np.testing.assert_allclose(np.floor(centres / 0.005) + 0.5, centres / 0.005, atol=1e-3)
    # Voxel centres by default, as ground truth everywhere; centroids on request.
    np.testing.assert_array_equal(pn.voxel_grid(points, 0.005), centres)
    centroids = pn.voxel_grid(points, 0.005, centres=False)
    assert len(centroids) == len(centres) and not np.array_equal(centroids, centres)
    box = pn.Box([0, 0, 0.2], [0.1, 0.1, 0.1], name="b")
    roi = pn.Roi([box])
    inside = pn.crop_to_roi(points, roi)
    assert len(inside) == roi.contains(points).sum() == box.contains(points).sum()
    outside = pn.crop_to_roi(points, roi, negative=True)
    assert len(inside) + len(outside) == len(points)
    assert len(pn.crop_to_roi(points, pn.Roi())) == 0


def test_files_round_trip(tmp_path):
    rng = np.random.default_rng(1)
    points = rng.normal(size=(1000, 3)).astype(np.float32)
    labels = rng.integers(0, 7, size=1000)
    for name, binary in [("a.pcd", True), ("b.pcd", False), ("c.ply", True), ("d.ply", False)]:
        pn.write_cloud(tmp_path / name, points, labels=labels, binary=binary)
        back, back_labels = pn.read_cloud(tmp_path / name, return_labels=True)
        np.testing.assert_array_equal(back, points)
        np.testing.assert_array_equal(back_labels, labels)
    roi = pn.Roi([pn.Box([1, 0, 1.15], [0.05, 0.05, 0.7], "main_stem"), pn.Box([0.1, 0.2, 0.3], [0.01, 0.02, 0.03])])
    pn.write_roi(tmp_path / "r.yaml", roi)
    assert repr(pn.read_roi(tmp_path / "r.yaml")) == repr(roi)
    depth = np.full((4, 5), 0.5, dtype=np.float32)
    depth[0, 0] = np.nan
    pn.write_depth_png(tmp_path / "d.png", depth)
    back = pn.read_depth_png(tmp_path / "d.png")
    assert np.isnan(back[0, 0]) and (back[1:] == 0.5).all()
    mesh = pn.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], labels=[pn.PART_LABELS["fruit"]])
    pn.write_mesh(tmp_path / "m.ply", mesh)
    back = pn.read_mesh(tmp_path / "m.ply")
    np.testing.assert_array_equal(back.vertices, mesh.vertices)
    assert back.labels.tolist() == [pn.PART_LABELS["fruit"]]


def test_poses_and_frames():
    T = pn.pose_matrix(V0)
    assert T.shape == (4, 4)
    np.testing.assert_allclose(pn.pose_vector(T), pn.pose_vector(V0), atol=1e-12)
    optical = pn.optical_from_body(V0)
    np.testing.assert_allclose(pn.body_from_optical(optical), pn.pose_vector(V0), atol=1e-12)
    R = pn.pose_matrix(optical)[:3, :3]
    np.testing.assert_allclose(R[:, 2], pn.pose_matrix(V0)[:3, 0], atol=1e-12)  # z optical = x body
    K = pn.CameraIntrinsics.l515("640x480").K
    camera = pn.CameraIntrinsics.from_matrix(K, 640, 480)
    assert camera.fx == K[0, 0] and camera.cy == K[1, 2]
