"""Serial protocol round trips over real pseudo-terminals and pyserial's loop://."""

from __future__ import annotations

import time

import numpy as np
import pytest

from softcath.hardware.errors import DeviceError
from softcath.hardware.ports import LineReader, open_port
from softcath.hardware.protocol import LineDecoder, checksum, encode_frame, encode_plain
from softcath.hardware.sensors import SerialSensor
from softcath.virtualbench.devices import VirtualLineDevice


def _collect(sensor: SerialSensor, n: int, timeout_s: float = 5.0):
    out = []
    deadline = time.monotonic() + timeout_s
    while len(out) < n and time.monotonic() < deadline:
        out.extend(sensor.poll())
    return out


def test_checksum_is_nmea_xor():
    # NMEA's published example sentence: $GPGLL,5057.970,N,00146.110,E,142451,A*27
    assert checksum(b"GPGLL,5057.970,N,00146.110,E,142451,A") == "27"


def test_decoder_counts_corrupt_and_gaps():
    dec = LineDecoder()
    assert dec.decode(encode_frame(0, 1.5)).value == 1.5
    bad = bytearray(encode_frame(1, 2.5))
    bad[3] = ord("9")
    assert dec.decode(bytes(bad)) is None
    assert dec.decode(encode_frame(4, 3.5)).seq == 4
    assert dec.decode(b"$5,1") is None  # cut-off line glued to nothing
    assert (dec.stats.received, dec.stats.corrupted, dec.stats.gaps, dec.stats.missing) == (
        2,
        2,
        1,
        3,
    )
    assert dec.stats.gap_log == [(1, 4)]


def test_sequence_wraps_without_a_gap():
    dec = LineDecoder()
    for seq in (65534, 65535, 65536, 65537):
        dec.decode(encode_frame(seq, 0.0))
    assert dec.stats.gaps == 0 and dec.stats.received == 4


def test_plain_mode_round_trip_over_loop_url():
    port = open_port("loop://", name="loop")
    for v in (0.25, -1e-3, 12.0):
        port.write(encode_plain(v))
    port.write(b"not-a-number\n")
    sensor = SerialSensor("loop://", framed=False, scale=2.0)
    # loop:// is a fresh loop per open: attach the sensor to the port we wrote into
    sensor._port, sensor._reader = port, LineReader(port)
    got = _collect(sensor, 3)
    assert [r.value for r in got] == [0.5, -2e-3, 24.0]
    _collect(sensor, 1, timeout_s=0.2)
    assert sensor.stats.corrupted == 1
    sensor.close()


def test_framed_round_trip_over_pty_with_faults():
    dev = VirtualLineDevice()
    values = np.linspace(0.0, 0.2, 50)
    with SerialSensor(dev.url, name="pressure sensor", scale=1e-3) as sensor:
        for i, v in enumerate(values):
            if i == 10:
                dev.emit_corrupted(v * 1e3)
            elif i == 20:
                dev.emit_partial(v * 1e3)  # glued onto the next line: both dropped
            elif i == 30:
                dev.skip(3)
            else:
                dev.emit(v * 1e3)
        got = _collect(sensor, 46)
        got += _collect(sensor, 1, timeout_s=0.2)
    # kept: all but #10 (corrupt), #20 and #21 (partial + glued) and #30 (never sent)
    expected = [v for i, v in enumerate(values) if i not in (10, 20, 21, 30)]
    np.testing.assert_allclose([r.value for r in got], expected, rtol=1e-8)
    st = sensor.stats
    assert st.corrupted == 2  # the flipped line and the glued line
    # sequence numbers lost: 10; 20, 21; and 3 skipped at #30 (seq 30-32, #31 is sent as 33)
    assert st.missing == 1 + 2 + 3 and st.gaps == 3
    dev.close()


def test_unplugged_device_keeps_received_rows_and_says_so():
    dev = VirtualLineDevice()
    sensor = SerialSensor(dev.url, name="encoder").open()
    for k in range(25):
        dev.emit(float(k))
    dev.emit_partial(99.0)
    got = _collect(sensor, 25)
    # the cut-off half line must have reached the reader before the device vanishes: bytes still in
    # the pseudo-terminal when its device side closes are never received (the kernel drops them)
    deadline = time.monotonic() + 5.0
    while sensor.pending_bytes == 0 and time.monotonic() < deadline:
        got += sensor.poll()
    assert sensor.pending_bytes > 0
    dev.unplug()
    with pytest.raises(DeviceError, match="encoder on /dev/pts/.* disconnected"):
        for _ in range(100):
            got += sensor.poll()
    assert [r.value for r in got] == [float(k) for k in range(25)]
    assert sensor.stats.partial == 1
    dev.close()


def test_open_failure_names_device_and_url():
    with pytest.raises(DeviceError, match=r"pressure sensor port = '/dev/does-not-exist'"):
        SerialSensor("/dev/does-not-exist", name="pressure sensor").open()


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


@settings(max_examples=200, deadline=None)
@given(
    seq=st.integers(min_value=0, max_value=10**6),
    value=st.floats(allow_nan=False, allow_infinity=False, min_value=-1e12, max_value=1e12),
)
def test_frame_round_trip_property(seq, value):
    s = LineDecoder().decode(encode_frame(seq, value))
    # values travel with 9 significant digits
    assert s.seq == seq % 65536 and s.value == pytest.approx(value, rel=1e-8, abs=1e-300)


@settings(max_examples=200, deadline=None)
@given(
    seq=st.integers(0, 65535), value=st.floats(-1e6, 1e6), pos=st.integers(0, 30), byte=st.integers(33, 126)
)
def test_any_single_character_change_is_caught(seq, value, pos, byte):
    line = bytearray(encode_frame(seq, value))
    body_end = line.index(b"*") + 3  # '$...*CS'
    i = pos % body_end
    orig = line[i]
    if orig == byte:
        return
    line[i] = byte
    s = LineDecoder().decode(bytes(line))
    original = LineDecoder().decode(encode_frame(seq, value))
    # XOR checksums catch every single-byte change of the payload or the checksum itself; the
    # only change that passes is the case of a hex checksum digit, which leaves the data intact
    assert s is None or (s == original and chr(byte).upper() == chr(orig).upper())
