"""Studies a designer runs on many designs: parameter sweeps and multi-objective optimisation.

* :mod:`profilegen.studies.sweep` — gear-set fields swept over a grid or a sample, one design per point;
* :mod:`profilegen.studies.optimize` — NSGA-II search of gear-set fields (``profilegen.optimize(spec, out_dir)``).
"""
