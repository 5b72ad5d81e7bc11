"""The cffi boundary: the generated declarations (_cdef), the loaded library
(_lib), numpy arrays in and out of C (_arrays), progress callbacks
(_progress) and the command line's start-up check (_startup).

The lowest layer of the package: nothing here imports any other part of
libkin except `libkin.errors` (which imports `_lib` back only to word a C
status). This __init__ imports nothing.
"""
