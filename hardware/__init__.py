"""Real devices: what a lab plugs in. The simulated rig is :mod:`softcath.virtualbench`.

Modules: ``protocol`` (sensor line framing), ``ports`` / ``sensors`` (pyserial
readers), ``stage`` (Zaber-style ASCII driver, syringe model), ``recorder``
with ``record_types`` and ``timebase`` (crash-safe 200 Hz CSV),
``circlefit`` / ``vision`` (with ``vision.scale``: px per mm) / ``frames`` / ``measure_video``
(tip measurement from camera frames), ``filtering`` (the paper's IIR filter).
Heavy imports (cv2, serial) happen inside functions.
"""

if __name__ != "softcath.hardware":  # the bare folder name would load a second copy of every module
    raise ImportError(
        "import softcath.hardware, not hardware: the top-level folders are rooms of the softcath package"
    )
