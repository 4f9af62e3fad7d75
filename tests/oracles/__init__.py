"""Cross-check models the tests compare the package against — not part of the installed package.

Each is an independent implementation, an analytic limit or a negative example of something the
package computes another way; the tests in tests/unit and tests/validation import them:

* :mod:`ring_on_cam` — the thin inextensible ring pressed by a cam with partial wrap, the limit
  the rim FEM converges to as δ/r_m → 0 (tests/validation/test_rim_oracle.py);
* :mod:`morley` — the cup-bottom plate by scikit-fem's Morley element, which decides between the
  plate models of profilegen.stress.plate (tests/validation/test_stress_plate.py);
* :mod:`cs_ring` — the circular spline as a thin ring (free, or on a housing foundation), a
  second implementation of the ratcheting estimate's CS ring (tests/unit/test_ratchet_ring.py);
* :mod:`naive_lp` — the printed phase-1 LP, which is not a contact solver (the negative example
  of tests/unit/test_contact_solvers.py);
* :mod:`solid_cup` — the plain 3D solid of the cup (27-node hexahedra, a quarter with the two
  symmetry planes), the check of the cup tier's Fourier formulation (tests/unit/test_cup3d.py);
* :mod:`clearance_rule` — the clearance map by its definition, pose by pose (tests/unit/test_clearance_search.py,
  tests/unit/test_face_width.py);
* :mod:`zdt1` — ZDT1, an analytic problem with a known Pareto front, for the optimiser's
  machinery (tests/unit/test_optimize.py).
"""
