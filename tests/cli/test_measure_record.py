"""`softcath measure` on rendered video, and `softcath record` edge cases (socket reconnect, bad ports)."""

from __future__ import annotations

import math
import socket
import threading
import time

import cv2
import numpy as np
import pytest

from softcath.cli.main import main
from softcath.design.measurement import read_recording
from softcath.hardware.protocol import encode_frame
from softcath.hardware.recorder import Recorder, RecorderConfig
from softcath.hardware.sensors import SerialSensor
from softcath.virtualbench.render import Scene, arc_end_pose, render_frame

SCENE = Scene(px_per_mm=40.0)
ANGLES = [15.0, 45.0, 90.0, 135.0]


@pytest.fixture(scope="module")
def video(tmp_path_factory):
    folder = tmp_path_factory.mktemp("frames")
    rng = np.random.default_rng(3)
    for i, deg in enumerate(ANGLES + [None]):
        if deg is None:  # a frame where the tip has left the picture
            img = np.full((SCENE.height_px, SCENE.width_px, 3), 205, np.uint8)
        else:
            img = render_frame(SCENE, curvature_per_mm=math.radians(deg) / 5.0, arc_length_mm=5.0, rng=rng)
        cv2.imwrite(str(folder / f"f{i:03d}.png"), img)
    return folder


@pytest.mark.parametrize("with_base", [True, False])
def test_measure_cli_writes_csv_and_overlay(video, tmp_path, capsys, with_base):
    args = ["measure", str(video), "--px-per-mm", "40", "--out", str(tmp_path), "--fps", "10"]
    if with_base:
        args += ["--base", f"{SCENE.base[0]},{SCENE.base[1]}", "--base-angle", "90"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "1 of 5 frames without a detectable tip" in out
    assert ("base found in the image" in out) != with_base
    header = (tmp_path / "measurements.csv").read_text().splitlines()[0]
    assert header == ("frame,time_s,curvature_per_mm,arc_length_mm,bend_angle_rad,tip_x_mm,tip_y_mm")
    d = read_recording(tmp_path / "measurements.csv")
    np.testing.assert_allclose(d["time_s"], np.arange(5) / 10.0)
    k = np.radians(ANGLES) / 5.0
    # known base: 2 % (as in test_vision); base found from the image: 3 %
    np.testing.assert_allclose(d["curvature_per_mm"][:4], k, rtol=0.02 if with_base else 0.03)
    assert np.isnan(d["curvature_per_mm"][4])
    tips = np.array([arc_end_pose(ki, 5.0)[:2] for ki in k])
    np.testing.assert_allclose(d["tip_x_mm"][:4], tips[:, 0], atol=0.05)
    np.testing.assert_allclose(d["tip_y_mm"][:4], tips[:, 1], atol=0.05)
    cap = cv2.VideoCapture(str(tmp_path / "overlay.avi"))
    assert cap.isOpened() and int(cap.get(cv2.CAP_PROP_FRAME_COUNT)) == 5
    cap.release()


def test_paper_method_cli_runs(video, tmp_path):
    assert (
        main(
            [
                "measure",
                str(video),
                "--px-per-mm",
                "40",
                "--method",
                "paper",
                "--dy",
                "8",
                "--base",
                f"{SCENE.base[0]},{SCENE.base[1]}",
                "--out",
                str(tmp_path),
            ]
        )
        == 0
    )
    d = read_recording(tmp_path / "measurements.csv")
    assert np.isfinite(d["curvature_per_mm"][:4]).all()


def test_measure_cli_bad_input(video, tmp_path, capsys):
    assert main(["measure", str(tmp_path / "nope.avi"), "--px-per-mm", "40", "--out", str(tmp_path)]) == 2
    assert "nope.avi: no such file" in capsys.readouterr().err
    assert main(["measure", str(video), "--px-per-mm", "0", "--out", str(tmp_path)]) == 2
    assert "--px-per-mm = 0: must be a finite number > 0" in capsys.readouterr().err
    assert main(["measure", str(video), "--px-per-mm", "40", "--base", "3", "--out", str(tmp_path)]) == 2
    assert "--base = '3': must be two numbers X,Y" in capsys.readouterr().err


def test_record_cli_bad_port(tmp_path, capsys):
    assert (
        main(
            [
                "record",
                "--pressure-port",
                "/dev/nonexistent-port",
                "--encoder-port",
                "loop://",
                "--out",
                str(tmp_path),
                "--duration",
                "1",
            ]
        )
        == 2
    )
    assert "pressure sensor port = '/dev/nonexistent-port': cannot open" in (capsys.readouterr().err)


def test_socket_device_reconnects_without_losing_rows(tmp_path):
    """A socket:// sensor drops its connection mid-run and comes back: the recorder reconnects."""
    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen(2)
    port = srv.getsockname()[1]
    n_per_conn = 200

    def device():
        seq = 0
        for _ in range(2):
            conn, _ = srv.accept()
            # pyserial's open() discards what is already waiting (reset_input_buffer); a
            # device that resumes streaming after a short start-up loses nothing
            time.sleep(0.3)
            for _ in range(n_per_conn):
                conn.sendall(encode_frame(seq, 0.001 * seq))
                seq += 1
            time.sleep(0.2)
            conn.close()  # the "unplug"
        srv.close()

    th = threading.Thread(target=device, daemon=True)
    th.start()
    rec = Recorder(
        tmp_path / "s.csv",
        pressure=SerialSensor(f"socket://127.0.0.1:{port}", name="pressure sensor"),
        config=RecorderConfig(clock="device", reconnect_timeout_s=1.0),
    )
    summary = rec.run()
    th.join(timeout=5)
    d = read_recording(tmp_path / "s.csv")
    # every sample of both connections, in order on the device clock (seq continues)
    np.testing.assert_allclose(d["pressure_MPa"], 0.001 * np.arange(2 * n_per_conn), atol=1e-12)
    assert any("reconnected" in m for m in summary.messages)
    assert summary.stop_reason == "pressure sensor lost"


def test_record_cli_with_stage_and_camera(video, tmp_path, capsys):
    from softcath.hardware.stage import ZaberStage
    from softcath.virtualbench.devices import VirtualClock, VirtualLineDevice, VirtualStage

    clock = VirtualClock(manual=True)
    stage_dev = VirtualStage(clock)
    with ZaberStage(stage_dev.url) as st:
        st.move_abs(1.25)
    clock.set(1e3)  # the move is long over
    press, enc = VirtualLineDevice(), VirtualLineDevice()
    press.start_paced(lambda t: 100.0, rate_hz=200.0)  # kPa
    enc.start_paced(lambda t: 7.0, rate_hz=200.0)
    rc = main(
        [
            "record",
            "--pressure-port",
            press.url,
            "--encoder-port",
            enc.url,
            "--stage-port",
            stage_dev.url,
            "--camera",
            str(video),
            "--px-per-mm",
            "40",
            "--base",
            f"{SCENE.base[0]},{SCENE.base[1]}",
            "--pressure-scale",
            "1e-3",
            "--duration",
            "1.0",
            "--run",
            "hold",
            "--out",
            str(tmp_path),
        ]
    )
    press.close()
    enc.close()
    stage_dev.close()
    assert rc == 0
    assert "recorded 201 rows" in capsys.readouterr().out
    d = read_recording(tmp_path / "measurements.csv")
    assert len(d["time_s"]) == 201
    np.testing.assert_allclose(d["pressure_MPa"], 0.1)
    np.testing.assert_allclose(d["encoder_mm"], 7.0)
    st_mm = d["stage_position_mm"][np.isfinite(d["stage_position_mm"])]
    assert st_mm.size and np.allclose(st_mm, 1.25, atol=1e-3)
    # the folder plays at 30 fps from the first row: frames 0-3 carry a tip, frame 4
    # (t = 4/30 s) has none, and there are no frames later: curvature only up to 3/30 s
    k = d["curvature_per_mm"]
    rel = d["time_s"] - d["time_s"][0]
    early = rel <= 3 / 30 + 1e-9
    assert early.sum() == 21 and np.isfinite(k[early]).all() and np.isnan(k[~early]).all()
    assert set(d["run"]) == {"hold"}
    assert (tmp_path / "record.json").exists()


def test_measure_cli_scale_from_a_chessboard(video, tmp_path, capsys):
    from softcath.virtualbench.render import render_chessboard

    # 40 px squares of 1 mm: the frames' 40 px/mm
    board = render_chessboard(squares=(10, 7), square_px=40.0, size=(640, 480), origin=(40.0, 40.0))
    cv2.imwrite(str(tmp_path / "board.png"), board)
    base = f"{SCENE.base[0]},{SCENE.base[1]}"
    args = [
        "measure",
        str(video),
        "--chessboard",
        str(tmp_path / "board.png"),
        "--pattern",
        "9x6",
        "--square-mm",
        "1",
        "--base",
        base,
        "--out",
        str(tmp_path / "m"),
    ]
    assert main(args) == 0
    assert "scale from the chessboard: 40.0" in capsys.readouterr().out
    d = read_recording(tmp_path / "m" / "measurements.csv")
    # sub-pixel corners give the scale to ~0.1 %, which passes straight into curvature
    np.testing.assert_allclose(d["curvature_per_mm"][:4], np.radians(ANGLES) / 5.0, rtol=0.02)
    assert (
        main(
            [
                "measure",
                str(video),
                "--chessboard",
                str(tmp_path / "board.png"),
                "--out",
                str(tmp_path / "m2"),
            ]
        )
        == 2
    )
    assert "--square-mm = None: is required with --chessboard" in capsys.readouterr().err


def test_a_refused_recording_leaves_an_earlier_recording_whole(tmp_path, cli):
    """A recording streams into measurements.csv from its first row; an earlier recording in the
    folder is refused up front instead of being truncated by a run that then hears nothing."""
    out = tmp_path / "rec"
    out.mkdir()
    (out / "measurements.csv").write_text("time_s,pressure_MPa,curvature_per_mm\n0,0.1,0.01\n")
    (out / "record.json").write_text("{}")
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    argv = ["record", "--pressure-port", "loop://", "--encoder-port", "loop://", "--duration", "0.1"]
    line = cli(*argv, "--out", out).error_line()
    assert "--out = " in line and "holds an earlier recording (measurements.csv)" in line
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
