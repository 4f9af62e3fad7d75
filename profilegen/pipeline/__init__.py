"""The stages run as one design: scenes, the design function, the incremental engine.

* :mod:`profilegen.pipeline.scenes` — the fidelity presets (``scenes.toml``) as :class:`Scene`;
* :mod:`profilegen.pipeline.budget` — what a design costs and can resolve, checked before it runs;
* :mod:`profilegen.pipeline.design` — :func:`~profilegen.pipeline.design.design`: every stage → :class:`Design`,
  with the verdict;
* :mod:`profilegen.pipeline.engine` — :class:`Engine`: the same design with each stage's result kept and reused;
* :mod:`profilegen.pipeline.scene_estimates` — how far each scene's numbers may be from the next scene's.
"""
