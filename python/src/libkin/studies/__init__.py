"""The solar-sail folding studies of the paper's Section 6: an application of
libkin that uses only its public API (libkin, libkin.atlas, libkin.symmetry,
libkin.plot, libkin.io).

sailstudy.hexagonal_study() and squarestudy.square_study() run the studies;
common.py holds what they share, sailmap.py reads the explorer's atlas as the
study's path map, sailmeasure.py measures a sail's folding, studyreport.py and
studyfigures.py write the report and its figures; cli.py is `libkin study`.
"""
