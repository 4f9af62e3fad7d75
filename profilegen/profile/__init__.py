"""The circular spline's tooth profile: from the FS tooth's motion to the outline a shop cuts.

* :mod:`profilegen.profile.envelope` — the envelope of the FS tooth family, its roots classified;
* :mod:`profilegen.profile.gearform` — the CS outline from the classified envelope, and the clearance map;
* :mod:`profilegen.profile.arcfit` — arc–line–arc (G1) fits of a CS flank;
* :mod:`profilegen.profile.rootfillet` — rounded corners of the CS tooth space, for wire EDM;
* :mod:`profilegen.profile.swept` — the brute-force swept region the envelope is checked against.
"""
