"""The virtual bench: a simulated rig that speaks the real devices' protocols.

Apart from the real-device code in :mod:`hardware`, which it drives
exactly as a lab would drive real hardware:

``plant``            the TRUTH plant (pressure in, curvature and pose out)
``truth_effects``    the hidden effects the plant can carry
``devices``          virtual sensors, encoder and stage on pseudo-terminals
``render``           synthetic camera frames of the bent tip
``bench``            the whole rig, recorded for real
``hidden_effects``   data sets with a hidden effect, for the missing-effect workflow
``hidden_protocols`` the excitation protocols those data sets use
"""

if __name__ != "softcath.virtualbench":  # the bare folder name would load a second copy of every module
    raise ImportError(
        "import softcath.virtualbench, not virtualbench: the top-level folders are rooms of the softcath "
        "package"
    )
