"""The solar-sail folding studies of the paper's Section 6: an application of
libkin that uses only its public API, each name from the public module or
subpackage that provides it (libkin.assembly, libkin.atlas, libkin.errors,
libkin.symmetry, libkin.plot, libkin.io, libkin.atomic, libkin.cliargs,
libkin.parallel, libkin.version), never the package root: the layer check
(tools/architecture.py) places the studies below it.

sailstudy.hexagonal_study() and squarestudy.square_study() run the studies;
common.py holds what they share, sailmap.py reads the explorer's atlas as the
study's path map, sailmeasure.py measures a sail's folding and names its
membrane's panels, studyreport.py and studyfigures.py write the report and
its figures; cli.py is `libkin study`.
"""
