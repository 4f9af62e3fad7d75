"""The output layer: every file, figure and report profilegen writes.

The stages compute frozen results and write nothing; this package turns them into files —
:mod:`.files` (a design's output folder, :func:`~.files.write_design`), :mod:`.cad` (DXF and
SVG), :mod:`.export` (atomic files, JSON, CSV), :mod:`.plot` (matplotlib figures),
:mod:`.report` (the HTML reports, figures rendered in worker processes) and :mod:`.folder`
(an output folder that changes as a whole). matplotlib is imported here and nowhere else in
the package (``tests/unit/test_import_graph.py``), inside the functions that draw, so
``import profilegen.output`` stays light.
"""
