"""The gear's geometry and motion, before any tooth profile is derived from it.

* :mod:`profilegen.geometry.teeth` — flexspline tooth profiles p(t) (DCTA, involute, points);
* :mod:`profilegen.geometry.wavegen` — wave-generator contours (the cam the FS bore is pressed onto);
* :mod:`profilegen.geometry.wgbearing` — the wave generator's flexible ball bearing;
* :mod:`profilegen.geometry.deformation` — the neutral line's deformation ω(φ), υ(φ) as a model;
* :mod:`profilegen.geometry.series` — series fits of a solved rim's deformation into that model;
* :mod:`profilegen.geometry.kinematics` — the FS tooth frame's motion in the CS frame;
* :mod:`profilegen.geometry.contour` — contours of true lines and circular arcs (what CAD and EDM take);
* :mod:`profilegen.geometry.fsform` — the flexspline's undeformed form as such a contour.
"""
