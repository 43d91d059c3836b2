"""The robot's loop from Python: simulated frames in, next views out, the same map and
views as the tool's `integrate` and `plan` on the same frames."""

import numpy as np
import pytest

import plantnbv as pn

from conftest import V0


@pytest.fixture(scope="module")
def frames(tmp_path_factory, placed):
    """Two frames of plant 3 (640 x 480) in a frames folder: v0 and a second view."""
    folder = tmp_path_factory.mktemp("frames") / "F"
    camera = pn.CameraIntrinsics.l515("640x480")
    sensor = pn.SimulatedDepthSensor(camera)
    sensor.set_plant(placed.plant)
    writer = pn.FramesFolderWriter(folder, camera)
    for stamp, pose in enumerate([V0, [0.62, -0.35, 1.2, 0.0, 0.0, 0.3827, 0.9239]]):
        frame = sensor.capture(T_W_C=pose)
        writer.append(frame["depth"], frame["T_W_O"], float(stamp))
    assert len(writer) == 2
    return folder


def test_a_frames_folder_reads_back_what_was_written(frames):
    folder = pn.FramesFolder(frames)
    assert len(folder) == 2 and folder.depth_scale == 1000.0
    assert folder.intrinsics.width == 640
    np.testing.assert_allclose(folder.poses[0], pn.optical_from_body(V0), atol=1e-9)
    depth = folder.depth(0)
    assert depth.shape == (480, 640) and depth.dtype == np.float32
    assert np.nanmax(depth) < 9.0 and np.isnan(depth).any()
    with pytest.raises(IndexError):
        folder.depth(2)


def test_session_gives_the_tools_map_and_views(frames, placed, cli, tmp_path):
    roi_file = tmp_path / "stem.yaml"
    pn.write_roi(roi_file, placed.rois["main_stem"])
    cli("integrate", frames, "-o", tmp_path / "tool.ot")
    tool = cli("plan", "--map", tmp_path / "tool.ot", "--roi", roi_file, "--seed", 5,
               "--json", parse_json=True)

    session = pn.Session(seed=5)
    session.camera = pn.CameraIntrinsics.l515("640x480")
    session.roi = pn.read_roi(roi_file)
    assert session.integrate_frames(pn.FramesFolder(frames)) == 2
    session.write_map(tmp_path / "ours.ot")
    assert (tmp_path / "ours.ot").read_bytes() == (tmp_path / "tool.ot").read_bytes()

    nbv = session.next_best_view()
    assert len(nbv) == len(tool["candidates"]) == 27
    assert list(nbv.indices) == [c["index"] for c in tool["candidates"]]
    assert list(nbv.gains) == [c["gain"] for c in tool["candidates"]]
    assert list(nbv.voxels_seen) == [c["voxels_seen"] for c in tool["candidates"]]
    np.testing.assert_array_equal(nbv.optical_poses,
                                  [c["optical_pose"] for c in tool["candidates"]])
    np.testing.assert_array_equal(nbv.best_optical_pose, tool["best"]["optical_pose"])
    np.testing.assert_array_equal(nbv.viewpoints[0], tool["best"]["viewpoint"])


def test_the_prior_predicts_what_plan_attends_to(frames, cli, tmp_path):
    cli("integrate", frames, "-o", tmp_path / "m.ot")
    tool = cli("plan", "--map", tmp_path / "m.ot", "--roi-source", "prior", "--json",
               parse_json=True)["attended_roi"]
    session = pn.Session()
    session.integrate_frames(pn.FramesFolder(frames))
    occupied = session.map.occupied_centres()
    sector = session.config.sector
    prior = pn.LeafNodePrior()
    predicted = prior.predict(occupied, sector)
    assert len(predicted) >= 3
    assert [b.name for b in predicted] == [b["name"] for b in tool]
    np.testing.assert_array_equal([b.center for b in predicted], [b["center"] for b in tool])
    np.testing.assert_array_equal([b.size for b in predicted], [b["size"] for b in tool])

    # detections+prior: the found boxes, then the same prediction; anchored on them
    # with anchor_on_found, as predict() with their centres as anchors.
    found = pn.Roi([pn.Box([1.0, 0.0, 1.05], [0.04, 0.04, 0.06], "node_a")])
    both = list(prior.predict_around(found, occupied, sector))
    assert [b.name for b in both] == ["node_a"] + [b.name for b in predicted]
    anchored = list(pn.LeafNodePrior(anchor_on_found=True)
                    .predict_around(found, occupied, sector))
    expected = prior.predict(occupied, sector, anchors=[[1.0, 0.0, 1.05]])
    np.testing.assert_array_equal([b.center for b in anchored[1:]],
                                  [b.center for b in expected])
    assert any(abs(b.center[2] - 1.09) < 1e-9 for b in expected)  # one internode up

    # Detected stem parts: the stem runs through them, as plan --stem-roi has it.
    stem = pn.Roi([pn.Box([1.0, 0.05, 1.0], [0.02, 0.02, 0.2], "main_stem_0")])
    write_roi = tmp_path / "stem.yaml"
    write_roi.write_text("boxes:\n  - {name: main_stem_0, center: [1.0, 0.05, 1.0], "
                         "size: [0.02, 0.02, 0.2]}\n")
    tool = cli("plan", "--map", tmp_path / "m.ot", "--roi-source", "prior", "--stem-roi",
               write_roi, "--json", parse_json=True)["attended_roi"]
    along = prior.predict(occupied, sector, stem=stem)
    np.testing.assert_array_equal([b.center for b in along], [b["center"] for b in tool])
    assert all(b.center[1] == 0.05 for b in along)
    np.testing.assert_array_equal(
        [b.center for b in prior.predict_around(pn.Roi(), occupied, sector, stem=stem)],
        [b.center for b in along])
    with pytest.raises(ValueError, match="internode_m"):
        pn.LeafNodePrior(internode_m=0)


def test_the_loop_on_simulated_frames_gains_what_it_plans(placed, sensor, camera):
    session = pn.Session(seed=1)
    session.camera = camera
    session.roi = placed.rois["main_stem"]
    reference = pn.crop_to_roi(pn.voxel_grid(pn.sample_mesh(placed.plant.mesh, 300000),
                                             0.003, centres=True), placed.rois["main_stem"])
    pose, f1, gains = V0, [], []
    for view in range(4):
        frame = sensor.capture(T_W_C=pose)
        session.integrate(frame["depth"], camera, frame["T_W_O"])
        occupied = pn.crop_to_roi(session.map.occupied_centres(), placed.rois["main_stem"])
        f1.append(pn.metrics(reference, occupied).f1)
        nbv = session.next_best_view()
        gains.append(nbv.gain)
        # The chosen view first (the best one 0.2 m or more from the frames' positions),
        # then by decreasing gain.
        assert nbv.gain == nbv.gains[0] and (np.diff(nbv.gains[1:]) <= 0).all()
        np.testing.assert_allclose(nbv.best_optical_pose, pn.optical_from_body(nbv.best_viewpoint),
                                   atol=1e-12)
        pose = nbv.best_viewpoint
    assert f1[-1] > f1[0] and all(b >= a - 0.02 for a, b in zip(f1, f1[1:]))
    assert gains[-1] < gains[0]


def test_points_integrate_as_depth_does(sensor, camera):
    frame = sensor.capture(T_W_C=V0)
    a, b = pn.OccupancyMap(), pn.OccupancyMap()
    a.integrate(frame["depth"], camera, frame["T_W_O"])
    points = pn.depth_to_points(frame["depth"], camera, frame["T_W_O"])
    assert points.shape == (240, 320, 3)
    b.insert(points.reshape(-1, 3), frame["T_W_O"][:3])
    assert a.counts() == b.counts() and a.counts()["occupied"] > 1000
    occupied = a.occupied_centres()
    assert (a.state(occupied) == pn.OCCUPIED).all()
    assert (a.probability(occupied) > 0.5).all()
    assert a.state([[5.0, 5.0, 5.0]])[0] == pn.UNKNOWN
    assert a.probability([[5.0, 5.0, 5.0]])[0] == 0.5


def test_fixed_candidates_and_the_baselines(sensor, camera):
    frame = sensor.capture(T_W_C=V0)
    sampler = pn.SectorSampler()
    candidates = sampler.sample(seed=3)
    assert candidates.shape == (27, 7)
    session = pn.Session()
    session.camera = camera
    session.integrate(frame["depth"], camera, frame["T_W_O"])
    session.set_candidates(candidates[:5])
    nbv = session.next_best_view()
    assert sorted(nbv.indices) == [0, 1, 2, 3, 4]
    np.testing.assert_allclose(nbv.viewpoints[0], candidates[nbv.indices[0]], atol=1e-12)
    session.set_candidates([pn.optical_from_body(c) for c in candidates[:3]], frame="optical")
    assert sorted(session.next_best_view().indices) == [0, 1, 2]

    session.set_candidate_sampler(sampler)
    session.set_planner(pn.PredefinedPlanner(pattern=3))
    centres = sampler.grid_cell_centres()
    first = session.next_best_view()
    assert any(np.allclose(first.viewpoints[0], c, atol=1e-12) for c in centres)
    session.set_planner(pn.RandomPlanner())
    assert len(session.next_best_view()) == 27


def test_the_papers_planner_is_one_setting_away(sensor, camera):
    frame = sensor.capture(T_W_C=V0)
    ours = pn.Session(seed=2)
    assert ours.config.unknown_only and ours.config.unknown_depth == 3
    paper = pn.Session(seed=2, unknown_only=False, unknown_depth=0)
    paper.set_planner(pn.NbvPlanner(view_spacing_m=0.0))
    for session in (ours, paper):
        session.camera = camera
        session.integrate(frame["depth"], camera, frame["T_W_O"])
    a, b = ours.next_best_view(), paper.next_best_view()
    # The same candidates; ours counts unknown voxels only, 3 per ray at most.
    np.testing.assert_array_equal(np.sort(a.indices), np.sort(b.indices))
    assert a.gains.max() < b.gains.max()
    with pytest.raises(ValueError):
        pn.NbvPlanner(view_spacing_m=-1.0)


def test_maps_round_trip_through_files(sensor, camera, tmp_path):
    frame = sensor.capture(T_W_C=V0)
    session = pn.Session()
    session.integrate(frame["depth"], camera, frame["T_W_O"])
    session.write_map(tmp_path / "m.ot")
    session.write_map(tmp_path / "m.bt")
    again = pn.OccupancyMap.read(tmp_path / "m.ot")
    assert again.counts() == session.map.counts()
    np.testing.assert_array_equal(again.occupied_centres(), session.map.occupied_centres())
    other = pn.Session()
    assert other.read_map(tmp_path / "m.ot") is True
    assert other.read_map(tmp_path / "m.bt") is False
