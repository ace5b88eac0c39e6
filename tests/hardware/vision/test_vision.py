"""Tip measurement on rendered frames with known curvature, arc length and tip position."""

from __future__ import annotations

import math

import numpy as np
import pytest

from softcath.design.errors import DesignError
from softcath.hardware.errors import FrameSourceError
from softcath.hardware.frames import VideoWriter, open_source
from softcath.hardware.vision import Calibration, draw_overlay, measure
from softcath.hardware.vision.scale import scale_from_chessboard, scale_from_points
from softcath.virtualbench.render import Scene, arc_end_pose, render_chessboard, render_frame

L_MM = 5.0
SCENE = Scene(px_per_mm=40.0, noise=2.0)
CAL = Calibration(px_per_mm=40.0, base_px=SCENE.base, base_angle_deg=90.0)
ANGLES = [10, 30, 60, 90, 120, 150]


def _frame(bend_deg, seed=0, scene=SCENE):
    k = math.radians(bend_deg) / L_MM
    return k, render_frame(scene, curvature_per_mm=k, arc_length_mm=L_MM, rng=np.random.default_rng(seed))


@pytest.mark.parametrize("bend_deg", ANGLES + [-45])
def test_default_method_within_two_percent(bend_deg):
    k, f = _frame(bend_deg)
    m = measure(f, CAL)
    assert m.ok
    # the requirement: 2 % of the true curvature over 10-150 degrees
    assert m.curvature_per_mm == pytest.approx(k, rel=0.02)
    tx, ty, th = arc_end_pose(k, L_MM)
    # arc length and tip from the red centroid: within half a pixel-ish (0.025 mm at 40 px/mm)
    # plus the anti-aliased disc edge; 0.03 mm = 1.2 px
    assert m.arc_length_mm == pytest.approx(L_MM, abs=0.03)
    assert (m.tip_x_mm, m.tip_y_mm) == pytest.approx((tx, ty), abs=0.03)
    assert m.bend_angle_rad == pytest.approx(th, rel=0.02)


@pytest.mark.parametrize("bend_deg", [20, 90, 150])
def test_default_method_finds_the_base_itself(bend_deg):
    scene = Scene(px_per_mm=40.0, base_px=(260.0, 400.0), base_angle_deg=70.0)
    k, f = _frame(bend_deg, scene=scene)
    m = measure(f, Calibration(px_per_mm=40.0))
    assert m.ok
    # the base found from the image: within 1.5 px and 1.5 degrees of the truth
    assert m.base_px == pytest.approx((260.0, 400.0), abs=1.5)
    assert m.base_angle_deg == pytest.approx(70.0, abs=1.5)
    # an estimated base pose costs accuracy (the constraint helps only with a
    # pose known to well under 1 px / 1 degree): allow 3 %
    assert m.curvature_per_mm == pytest.approx(k, rel=0.03)


def test_paper_method_error_is_measured_and_reported():
    errs = {}
    for deg in ANGLES:
        k, f = _frame(deg)
        m = measure(f, CAL, method="paper")
        errs[deg] = (m.curvature_per_mm / k - 1) * 100 if m.ok else float("nan")
    print("paper method curvature error, % by bend angle:", {d: round(e, 1) for d, e in errs.items()})
    # the paper's pipeline underestimates curvature on such renders (by tens of per cent);
    # the test asks for a large underestimate: it is what the paper's pipeline does, not a bug here
    assert all(abs(errs[d]) > 5 for d in (30, 60, 90))
    default = [abs(measure(_frame(d)[1], CAL).curvature_per_mm / _frame(d)[0] - 1) for d in ANGLES]
    assert max(default) < min(abs(errs[d]) for d in (30, 60, 90))


def test_frame_without_tip_is_reported_not_raised():
    blank = np.full((240, 320, 3), 200, np.uint8)
    m = measure(blank, Calibration(px_per_mm=40.0, base_px=(160, 200)))
    assert not m.ok and math.isnan(m.curvature_per_mm) and m.reason
    assert not measure(blank, Calibration(px_per_mm=40.0)).ok
    assert not measure(blank, Calibration(px_per_mm=40.0), method="paper").ok
    draw_overlay(blank, m, Calibration(px_per_mm=40.0))


def test_bad_parameters_name_the_bound():
    with pytest.raises(DesignError, match=r"px_per_mm = -3: must be a finite number > 0"):
        Calibration(px_per_mm=-3.0)
    with pytest.raises(DesignError, match="method = 'hough': must be one of default, paper"):
        measure(np.zeros((10, 10, 3), np.uint8), CAL, method="hough")


def test_chessboard_and_two_point_scale():
    img = render_chessboard(squares=(10, 7), square_px=30.0)
    # 30 px squares of 2.5 mm: 12 px/mm; sub-pixel corners on a clean board: 0.5 %
    assert scale_from_chessboard(img, pattern=(9, 6), square_mm=2.5) == pytest.approx(12, rel=5e-3)
    assert scale_from_points((0, 0), (30, 40), 10.0) == pytest.approx(5.0)
    with pytest.raises(FrameSourceError, match="chessboard with 8x8 inner corners: not found"):
        scale_from_chessboard(img, pattern=(8, 8), square_mm=2.5)


def test_video_and_folder_sources_round_trip(tmp_path):
    import cv2

    ks = []
    with VideoWriter(tmp_path / "v.avi", fps=25.0, size=(SCENE.width_px, SCENE.height_px)) as w:
        for i, deg in enumerate((20, 60, 100)):
            k, f = _frame(deg, seed=i)
            ks.append(k)
            w.write(f)
            (tmp_path / "imgs").mkdir(exist_ok=True)
            cv2.imwrite(str(tmp_path / "imgs" / f"f{i:03d}.png"), f)
    for spec, fps in ((tmp_path / "v.avi", 25.0), (tmp_path / "imgs", 30.0)):
        with open_source(spec) as src:
            frames = list(src)
        assert [fr.index for fr in frames] == [0, 1, 2]
        assert frames[2].time_s == pytest.approx(2 / fps)
        got = [measure(fr.image, CAL).curvature_per_mm for fr in frames]
        # MJPG compression adds blocking artefacts: 3 % instead of 2 %
        np.testing.assert_allclose(got, ks, rtol=0.03)


def test_unreadable_sources_say_so(tmp_path):
    with pytest.raises(FrameSourceError, match="no such file"):
        open_source(tmp_path / "missing.avi")
    (tmp_path / "empty").mkdir()
    with pytest.raises(FrameSourceError, match="holds no images"):
        open_source(tmp_path / "empty")
    (tmp_path / "junk.avi").write_bytes(b"not a video")
    with pytest.raises(FrameSourceError, match="junk.avi"):
        list(open_source(tmp_path / "junk.avi"))


@pytest.mark.parametrize("method", ["default", "paper"])
def test_overlay_draws_the_fitted_arc_on_the_tube(method):
    from softcath.virtualbench.render import arc_points

    k, f = _frame(80)
    m = measure(f, CAL, method=method)
    ov = draw_overlay(f, m, CAL)
    green = (ov[..., 1] > 180) & (ov[..., 0] < 80) & (ov[..., 2] < 80)
    if method == "default":
        # the default fit passes within 3 px of the true centre line everywhere
        pts = arc_points(k, np.linspace(0.3, L_MM - 0.6, 12)) * 40.0
        u = np.round(SCENE.base[0] + pts[:, 0]).astype(int)
        v = np.round(SCENE.base[1] - pts[:, 1]).astype(int)
        assert all(green[vi - 3 : vi + 4, ui - 3 : ui + 4].any() for ui, vi in zip(u, v, strict=True))
    else:  # the paper's (biased) circle is drawn, wherever it lies
        assert green.sum() > 100
    assert ov[4:20, 6:200].mean() < 120  # the dark text box with the numbers


def test_camera_intrinsics_recover_a_known_focal_length():
    import cv2

    from softcath.hardware.vision.scale import camera_intrinsics

    # board: 10x7 squares of 30 px at origin (40, 40) -> 1 board px = 0.1 mm (3 mm squares)
    board = render_chessboard(squares=(10, 7), square_px=30.0, size=(400, 300), origin=(40.0, 40.0))
    k_true = np.array([[800.0, 0, 320], [0, 800.0, 240], [0, 0, 1]])
    s = np.array([[0.1, 0, -4.0 - 0.05], [0, 0.1, -4.0 - 0.05], [0, 0, 1]])  # px -> mm, first corner
    views = []
    for rx, ry, tz in [(0.3, 0, 60), (-0.3, 0.1, 65), (0, 0.35, 62), (0.2, -0.3, 58), (-0.2, -0.2, 70)]:
        r, _ = cv2.Rodrigues(np.array([rx, ry, 0.0]))
        h = k_true @ np.column_stack([r[:, 0], r[:, 1], [-12.0, -8.0, tz]]) @ s
        views.append(cv2.warpPerspective(board, h, (640, 480), borderValue=(230, 230, 230)))
    k, _, rms = camera_intrinsics(views, pattern=(9, 6), square_mm=3.0)
    # exact synthetic projections: reprojection error well under a pixel, focal length to 2 %
    assert rms < 0.5
    assert k[0, 0] == pytest.approx(800.0, rel=0.02) and k[1, 1] == pytest.approx(800.0, rel=0.02)
    with pytest.raises(DesignError, match="images = 2: must hold >= 3 chessboard views"):
        camera_intrinsics(views[:2], pattern=(9, 6), square_mm=3.0)
