"""Bad input is a Python exception with the library's one-line message, never a crash."""

import numpy as np
import pytest

import plantnbv as pn

GOOD = np.zeros((4, 3))


@pytest.mark.parametrize("points, error, message", [
    (np.zeros((4, 2)), ValueError,
     r"^reference: expected an \(N, 3\) array of float32 or float64, got a float64 array "
     r"of shape \(4, 2\)$"),
    (np.zeros(3), ValueError, r"got a float64 array of shape \(3,\)$"),
    (np.zeros((4, 3), dtype=np.int64), ValueError, r"got a int64 array of shape \(4, 3\)$"),
    (np.zeros((4, 3), dtype=np.float16), ValueError, "float16"),
    (np.zeros((2, 4, 3)), ValueError, r"shape \(2, 4, 3\)"),
    ("points.ply", TypeError, r"^reference: expected .*, got 'str'$"),
    (None, TypeError, "got 'NoneType'"),
    ([[1, 2, "a"]], TypeError, "got 'list'"),
    ({"x": 1}, TypeError, "got 'dict'"),
])
def test_bad_clouds_name_the_argument_and_the_expected_shape(points, error, message):
    with pytest.raises(error, match=message):
        pn.metrics(points, GOOD)


def test_bad_values_are_value_errors_with_the_library_message():
    with pytest.raises(pn.InvalidArgumentError) as e:
        pn.metrics(GOOD, GOOD, rho=0.0)
    assert isinstance(e.value, ValueError) and isinstance(e.value, pn.Error)
    assert "rho" in str(e.value) or "threshold" in str(e.value)
    with pytest.raises(ValueError, match="leaf"):
        pn.voxel_grid(GOOD, leaf_m=-1.0)
    with pytest.raises(ValueError, match="index"):
        pn.default_plant(10)
    with pytest.raises(ValueError, match="growth|stage"):
        pn.generate_plant(growth_stage=2.0)
    with pytest.raises(ValueError, match="kind: expected one of whole_plant"):
        pn.generate_plant().roi("leaves")
    with pytest.raises(ValueError, match="resolution"):
        pn.OccupancyMap(resolution_m=-0.1)
    with pytest.raises(ValueError, match="nbv, predefined|planner"):
        pn.run_trial(pn.place_plant(seed=0), planner="greedy", views=1)


@pytest.mark.parametrize("pose, message", [
    ([0, 0, 0, 0, 0, 0, 2], "unit quaternion"),
    ([0, 0, np.nan, 0, 0, 0, 1], "finite"),
    (np.eye(3), r"4x4 rigid transform or \(7,\)"),
    (np.diag([2.0, 1, 1, 1]), "rigid transform"),
    (np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1.0]]), "rigid"),
])
def test_bad_poses_are_value_errors(pose, message):
    with pytest.raises(ValueError, match=message):
        pn.pose_matrix(pose)


def test_wrong_types_are_type_errors():
    with pytest.raises(TypeError):
        pn.pose_matrix("identity")
    with pytest.raises(TypeError):
        pn.metrics(GOOD, GOOD, rho="small")
    with pytest.raises(TypeError):
        pn.crop_to_roi(GOOD, [pn.Box([0, 0, 0], [1, 1, 1])])
    with pytest.raises(TypeError, match="unknown argument 'resolution'"):
        pn.OccupancyMap(resolution=0.005)
    with pytest.raises(TypeError, match="T_W_C .* or T_W_O"):
        pn.SimulatedDepthSensor().capture()


def test_bad_labels_and_triangles():
    with pytest.raises(ValueError, match=r"labels: expected 4 values \(one per point\), got 3"):
        pn.voxel_grid(GOOD, labels=np.zeros(3, dtype=np.int32))
    with pytest.raises(ValueError, match=r"labels\[1\]: expected an integer"):
        pn.voxel_grid(GOOD, labels=np.array([0, -1, 0, 0]))
    with pytest.raises(ValueError, match="labels: expected"):
        pn.voxel_grid(GOOD, labels=np.zeros(4))
    with pytest.raises(ValueError, match=r"triangles\[0\]: vertex index 5 is not in \[0, 3\)"):
        pn.Mesh(np.eye(3), [[0, 1, 5]])
    with pytest.raises(ValueError, match=r"labels\[0\]: expected a part label 0-7"):
        pn.Mesh(np.eye(3), [[0, 1, 2]], labels=[9])


def test_nan_in_boxes_depth_and_origins():
    with pytest.raises(ValueError, match=r"center: expected 3 finite numbers"):
        pn.Box([0, np.nan, 0], [1, 1, 1])
    with pytest.raises(ValueError, match=r"size"):
        pn.Box([0, 0, 0], [1, -1, 1])
    with pytest.raises(ValueError, match=r"origin: expected 3 finite numbers"):
        pn.OccupancyMap().insert(GOOD, [np.inf, 0, 0])
    with pytest.raises(ValueError, match=r"depth: expected an \(H, W\) depth image"):
        pn.Session().integrate(np.zeros((4, 4, 1)), pn.CameraIntrinsics.l515(),
                               [0, 0, 0, 0, 0, 0, 1])
    with pytest.raises(ValueError, match="a 4x4 image .* camera of 1024x768"):
        pn.Session().integrate(np.zeros((4, 4)), pn.CameraIntrinsics.l515(),
                               [0, 0, 0, 0, 0, 0, 1])


@pytest.mark.parametrize("call", [
    lambda p: pn.read_cloud(p / "missing.pcd"),
    lambda p: pn.read_mesh(p / "missing.dae"),
    lambda p: pn.read_roi(p / "missing.yaml"),
    lambda p: pn.read_depth_png(p / "missing.png"),
    lambda p: pn.read_geometry(p / "missing.ply"),
    lambda p: pn.OccupancyMap.read(p / "missing.ot"),
    lambda p: pn.FramesFolder(p / "missing"),
    lambda p: pn.place_plant(model=str(p / "missing.obj")),
    lambda p: pn.campaign_status(p),
    lambda p: pn.campaign_timing(p),
])
def test_missing_files_are_file_not_found_errors(tmp_path, call):
    with pytest.raises(FileNotFoundError) as e:
        call(tmp_path)
    assert isinstance(e.value, pn.IoError) and isinstance(e.value, OSError)
    assert "\n" not in str(e.value) and str(tmp_path) in str(e.value)


def test_malformed_files_are_format_errors(tmp_path):
    bad = tmp_path / "bad.pcd"
    bad.write_text("not a pcd file\n")
    with pytest.raises(pn.FormatError, match="bad.pcd"):
        pn.read_cloud(bad)
    (tmp_path / "x.xyz").write_text("1 2 3\n")
    with pytest.raises(pn.FormatError, match=r"extension '\.xyz' \(expected \.pcd or \.ply\)"):
        pn.read_cloud(tmp_path / "x.xyz")
    (tmp_path / "rois.yaml").write_text("boxes:\n  - center: [0, 0]\n    size: [1, 1, 1]\n")
    with pytest.raises(pn.FormatError, match=r"boxes\[0\]\.center"):
        pn.read_roi(tmp_path / "rois.yaml")
    (tmp_path / "d.pcd").mkdir()
    with pytest.raises(pn.IoError, match="is a directory"):
        pn.read_cloud(tmp_path / "d.pcd")


def test_unwritable_paths_are_os_errors(tmp_path):
    with pytest.raises(OSError):
        pn.write_cloud(tmp_path / "no" / "such" / "dir.pcd", GOOD)


def test_a_camera_made_invalid_after_construction_is_refused_where_it_is_used():
    camera = pn.CameraIntrinsics(4, 4, 2.0, 2.0, 1.5, 1.5)
    camera.fx = 0.0
    with pytest.raises(ValueError, match="fx"):
        pn.OccupancyMap().integrate(np.ones((4, 4)), camera, [0, 0, 0, 0, 0, 0, 1])
    with pytest.raises(ValueError, match="fx"):
        pn.Session().integrate(np.ones((4, 4)), camera, [0, 0, 0, 0, 0, 0, 1])
