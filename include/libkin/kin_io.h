/* libkin: model files. Reads and writes the JSON model format described in
 * docs/model_format.md (the same format the Python package reads and writes),
 * from a file or from text held in memory.
 *
 * Errors: every call takes an optional errbuf (may be NULL) that receives,
 * on failure, a NUL-terminated message truncated to errlen bytes ("" on
 * success). Messages name the field and its position as the Python loader does
 * ("bars[3].joints[1]: joint 7 out of range 0..5"), or the line and column of
 * a JSON syntax error; loads from a file start with the file's path.
 * Status codes: KIN_EIO (the file could not be opened, read or written, or
 * is not a regular file), KIN_ELIMIT (the file is larger than the load
 * limit, KIN_LOAD_MAX_BYTES unless kin_assembly_load_limited() raises it),
 * KIN_EFORMAT (the text is not JSON, or breaks a rule of the schema), or
 * a code of kin_assembly_create() for a document that is well-formed but
 * describes an invalid assembly (KIN_EINVAL fewer than 2 joints, KIN_ESELFBAR,
 * KIN_EDUPBAR, KIN_EGEOM zero-length bar, KIN_ENOFREE). */
#ifndef KIN_IO_H
#define KIN_IO_H

#include <stddef.h>
#include "kin_export.h"
#include "kin_assembly.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest model file kin_assembly_load() reads: 64 MiB (a model of about
 * 200 000 bars; kin_assembly_load_limited() sets another limit). */
#define KIN_LOAD_MAX_BYTES 67108864u

/* Create an assembly from the JSON model file at `path` (UTF-8 text).
 *  path    file name, NUL-terminated.
 *  out     receives the new handle (free with kin_assembly_free); set to
 *          NULL on failure.
 * Only a regular file of at most KIN_LOAD_MAX_BYTES bytes is read: a FIFO,
 * a device or a directory is refused (KIN_EIO) without blocking, a larger
 * file with KIN_ELIMIT before it is read.
 * The joints' xyz become the initial configuration; "length" (given for
 * every bar or for none) the rest lengths, else the initial lengths. The
 * optional "name", joint "label"s and bar "kind"s are checked for type but
 * not kept: the handle has no place for them. Other keys are ignored.
 * Returns KIN_OK, KIN_ENULL (path or out NULL), KIN_EIO, KIN_EFORMAT,
 * KIN_ELIMIT, KIN_ENOMEM, or a kin_assembly_create() code (see above). */
KIN_API int kin_assembly_load(const char *path, kin_assembly **out, char *errbuf,
                              size_t errlen);

/* As kin_assembly_load(), with the size limit max_bytes in place of
 * KIN_LOAD_MAX_BYTES (0 means KIN_LOAD_MAX_BYTES). A file larger than
 * max_bytes, or one that grows past it while read, gives KIN_ELIMIT; at most
 * max_bytes + 2 bytes of buffer are allocated for the text. */
KIN_API int kin_assembly_load_limited(const char *path, size_t max_bytes, kin_assembly **out,
                                      char *errbuf, size_t errlen);

/* As kin_assembly_load(), from the first `len` bytes of `text` (need not be
 * NUL-terminated, so a Fortran CHARACTER buffer can be passed with its
 * length; C callers pass strlen(text)). The caller keeps `text`.
 * No size limit: the caller already holds the text.
 * Returns as kin_assembly_load() except KIN_EIO and KIN_ELIMIT. */
KIN_API int kin_assembly_load_string(const char *text, size_t len, kin_assembly **out,
                                     char *errbuf, size_t errlen);

/* Write the assembly as a JSON model file at `path` (created or replaced).
 *  name  optional model name written as "name" (NULL = no name).
 * Written: the dimension, the CURRENT configuration as each joint's xyz,
 * the fixity as "free" flags, the bars in order and their rest lengths as
 * "length", numbers with 17 significant digits, so that
 * kin_assembly_load(path) rebuilds the same model bit for bit: the same
 * coordinates, fixity, bars (order and orientation) and rest lengths. Not
 * written: options and path state (path length, orientation, step count);
 * the loaded assembly starts a fresh path at the saved configuration, as
 * after kin_set_coords(). The assembly is not changed.
 * Written whole or not at all: into a temporary file <path>.tmp.XXXXXX in
 * the same folder, fsynced, then renamed over path; on any failure (e.g. a
 * full disk: KIN_EIO) the temporary file is removed and a file already at
 * path is left as it was. (A path that is a device, e.g. /dev/stdout, is
 * written in place.)
 * Returns KIN_OK, KIN_ENULL (a or path NULL), KIN_EIO, KIN_ENOMEM, KIN_EGEOM
 * (a non-finite coordinate or length, which a valid handle never holds),
 * KIN_EINVAL (name is not valid UTF-8). */
KIN_API int kin_assembly_save(const kin_assembly *a, const char *name, const char *path,
                              char *errbuf, size_t errlen);

/* As kin_assembly_save(), into a new NUL-terminated string.
 *  text  receives the string (NULL on failure); the caller releases it with
 *        kin_free_string().
 *  len   optional (may be NULL): receives strlen(*text).
 * Returns KIN_OK, KIN_ENULL (a or text NULL), KIN_ENOMEM, KIN_EGEOM, KIN_EINVAL
 * (name is not valid UTF-8). */
KIN_API int kin_assembly_save_string(const kin_assembly *a, const char *name, char **text,
                                     size_t *len, char *errbuf, size_t errlen);

/* Release a string returned by kin_assembly_save_string(). NULL does
 * nothing. */
KIN_API void kin_free_string(char *text);

#ifdef __cplusplus
}
#endif

#endif /* KIN_IO_H */
