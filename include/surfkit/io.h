/* Mesh file formats: OFF, OBJ, PLY (ascii, binary little/big endian), STL (ascii, binary).
 *
 * Readers parse from memory first; the file functions are thin wrappers. Errors name the file, the
 * line (text formats) or byte offset (binary formats) and what is wrong, as one line:
 *   "lion.off:17: face 12 has index 9001 but the file has 8356 vertices"
 * Readers check declared counts against the input size before allocating. Writers write to a
 * temporary file and rename it into place when complete. */
#ifndef SURFKIT_IO_H
#define SURFKIT_IO_H

#include "surfkit/core.h"
#include "surfkit/mesh.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    SK_FORMAT_AUTO = 0, /* from the file name's extension (reading: also from the content) */
    SK_FORMAT_OFF,
    SK_FORMAT_OBJ,
    SK_FORMAT_PLY,
    SK_FORMAT_STL,
    SK_FORMAT_UNKNOWN
} sk_format;

typedef struct sk_read_opts {
    sk_format format; /* 0 = from extension, then content */
} sk_read_opts;

typedef struct sk_write_opts {
    sk_format format;  /* 0 = from extension */
    bool ascii;        /* PLY and STL: ascii instead of the binary default */
    bool no_normals;   /* do not write the soup's normals */
    bool no_uvs;       /* do not write the soup's uvs */
} sk_write_opts;

/* Format from a path's extension (case-insensitive): .off .obj .ply .stl; SK_FORMAT_UNKNOWN else. */
SK_API sk_format sk_format_from_path(const char *path);
/* A short name ("OFF", "OBJ", "PLY", "STL", "auto", "unknown"); never NULL. */
SK_API const char *sk_format_name(sk_format format);

/* Parses size bytes (need not be NUL-terminated; never modified) into a new soup. The format is
 * opts->format, else the extension of name, else guessed from the content (PLY magic, OFF
 * keyword, "solid" + "facet" for ascii STL, 84 + 50 n bytes for binary STL, OBJ statements).
 * name is used in error messages (usually the file's base name).
 * Guarantees: on success every face has at least 3 indices, all in range, and every coordinate
 * (and normal / uv) is finite; normals / uvs are present only when the file has them. On failure
 * *out is NULL, nothing leaks, and err holds one line "NAME:LINE: what" (text) or "NAME: byte
 * OFFSET: what" (binary) with SK_ERR_PARSE (SK_ERR_NOMEM if memory ran out). Declared counts are
 * checked against the input size before anything is allocated for them. */
SK_API sk_status sk_soup_read_memory(const void *data, size_t size, const char *name,
                                     const sk_read_opts *opts, sk_soup **out, sk_error *err);
/* Reads a whole file and parses it as sk_soup_read_memory does, naming it by its base name in
 * parse errors. SK_ERR_IO (message with the path) when the file cannot be opened or read. */
SK_API sk_status sk_soup_read(const char *path, const sk_read_opts *opts, sk_soup **out, sk_error *err);

/* Writes the soup in opts->format (else from the path's extension). Text formats use the
 * shortest decimal that reads back as the same double; binary PLY stores doubles; binary STL
 * floats (the only type STL has). Refuses (SK_ERR_ARG, no file created) a soup with an index out
 * of range or a face of fewer than 3 vertices. The file is written to a temporary in the target
 * folder and renamed into place only when complete: on any error no file (and no temporary) is
 * left behind. */
SK_API sk_status sk_soup_write(const char *path, const sk_soup *soup, const sk_write_opts *opts,
                               sk_error *err);
/* Writes to a malloc'ed buffer (*data, *size; the caller frees *data); opts->format must be given.
 * Same bytes as sk_soup_write would write; on failure *data is NULL. */
SK_API sk_status sk_soup_write_memory(const sk_soup *soup, const sk_write_opts *opts, void **data,
                                      size_t *size, sk_error *err);

/* Convenience: sk_soup_read + sk_mesh_from_soup (a topology error is prefixed with the file's
 * base name); sk_mesh_to_soup + sk_soup_write (same guarantees as sk_soup_write). */
SK_API sk_status sk_mesh_read(const char *path, const sk_read_opts *opts, sk_mesh **out, sk_error *err);
SK_API sk_status sk_mesh_write(const char *path, const sk_mesh *mesh, const sk_write_opts *opts,
                               sk_error *err);

#ifdef __cplusplus
}
#endif
#endif
