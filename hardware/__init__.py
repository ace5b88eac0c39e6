"""softcath hardware package: the paper's bench and a virtual one that speaks the same protocols.

Modules: ``protocol`` (sensor line framing), ``ports`` / ``sensors`` (pyserial
readers), ``stage`` (Zaber-style ASCII driver, syringe model),
``virtual_devices`` (pty devices), ``render`` (synthetic frames),
``circlefit`` / ``vision`` (``tipvision`` re-exports it) / ``calibration`` / ``frames`` /
``measure_video`` (tip measurement), ``recorder`` (crash-safe 200 Hz CSV),
``filtering`` (the paper's IIR filter), ``bench`` (the virtual bench).
Heavy imports (cv2, serial) happen inside functions.
"""
