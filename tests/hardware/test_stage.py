"""The Zaber-style ASCII driver against the virtual stage over a pseudo-terminal."""

from __future__ import annotations

import numpy as np
import pytest

from softcath.design.errors import DesignError
from softcath.hardware.errors import DeviceError
from softcath.hardware.stage import (
    SyringeModel,
    ZaberStage,
    format_command,
    lrc,
    parse_reply,
    sine_trajectory,
)
from softcath.virtualbench.devices import VirtualClock, VirtualStage


def test_lrc_makes_byte_sum_zero():
    # the LRC's defining property: message bytes plus checksum sum to 0 mod 256
    body = "01 0 OK IDLE -- 0"
    assert (sum(body.encode()) + int(lrc(body), 16)) % 256 == 0
    assert format_command("move abs 4321", axis=1) == b"/1 1 move abs 4321\n"
    line = format_command("get pos", checksums=True).decode()
    cs_body, cs = line[1:].strip().split(":")
    assert (sum(cs_body.encode()) + int(cs, 16)) % 256 == 0


def test_parse_reply_rejects_bad_checksum():
    good = "@01 1 OK IDLE -- 4321"
    assert parse_reply(good).data == "4321"
    body = good[1:]
    assert parse_reply(f"@{body}:{lrc(body)}").status == "IDLE"
    with pytest.raises(DeviceError, match="checksum"):
        parse_reply(f"@{body}:00")


@pytest.mark.parametrize("checksums", [False, True])
def test_driver_moves_virtual_stage(checksums):
    clock = VirtualClock(manual=True)
    stage_dev = VirtualStage(clock)
    with ZaberStage(stage_dev.url, checksums=checksums) as stage:
        stage.home()
        stage.move_abs(2.0)
        clock.set(100.0)  # long after the move finished
        assert stage.position_mm() == pytest.approx(2.0, abs=stage.microstep_mm)
        assert stage.status().status == "IDLE"
        stage.move_rel(-0.5)
        clock.set(200.0)
        assert stage.position_mm() == pytest.approx(1.5, abs=stage.microstep_mm)
        with pytest.raises(DeviceError, match="rejected 'move abs -1008'"):
            stage.move_abs(-0.1)
    stage_dev.close()


def test_constant_speed_move_and_sine_follow_the_clock():
    clock = VirtualClock(manual=True)
    dev = VirtualStage(clock)
    with ZaberStage(dev.url) as stage:
        stage.set_max_speed(1.0)  # mm/s
        stage.move_abs(3.0)
        clock.set(1.5)  # halfway: 1.5 mm at 1 mm/s (virtual stage has no ramp)
        assert stage.position_mm() == pytest.approx(1.5, abs=2e-3)
        assert stage.status().status == "BUSY"
        clock.set(10.0)
        stage.move_sine(0.5, 2.0, cycles=3)
        t = np.array([0.3, 0.9, 1.7, 5.2])
        for ti in t:
            clock.set(10.0 + ti)
            expect = sine_trajectory(ti, amplitude_mm=0.5, period_s=2.0, start_mm=3.0)
            # one microstep of rounding on the wire
            assert stage.position_mm() == pytest.approx(float(expect), abs=2 * stage.microstep_mm)
        clock.set(10.0 + 6.5)  # 3 cycles done: back at rest at the start
        assert stage.position_mm() == pytest.approx(3.0, abs=2 * stage.microstep_mm)
        assert stage.status().status == "IDLE"
    dev.close()


def test_no_reply_is_a_clear_error():
    dev = VirtualStage(device=2)  # answers only device 2
    with ZaberStage(dev.url, device=1, reply_timeout_s=0.2) as stage:
        with pytest.raises(DeviceError, match="no reply within 0.2 s"):
            stage.home()
    dev.close()


def test_syringe_model_round_trip_and_bounds():
    syr = SyringeModel(plunger_diameter_mm=4.0, compliance_mm3_per_MPa=50.0)
    # pi/4 * 16 mm^2 * 1 mm / 50 mm^3/MPa
    assert syr.pressure_MPa(1.0) == pytest.approx(np.pi * 4 / 50)
    assert syr.displacement_mm(syr.pressure_MPa(0.37)) == pytest.approx(0.37)
    with pytest.raises(DesignError, match=r"syringe.compliance_mm3_per_MPa = -1: must be > 0"):
        SyringeModel(compliance_mm3_per_MPa=-1.0)
