/* common/io/mesh_io_ply_header.h — the parsed header of a PLY file, shared by the two halves of
 * lumesh's own PLY reader: mesh_io_ply_header.c (the header, and its counts checked against the
 * bytes that follow it) and mesh_io_ply_read.c (the body, into a scene). Not for other files. */
#ifndef LM_COMMON_MESH_IO_PLY_HEADER_H
#define LM_COMMON_MESH_IO_PLY_HEADER_H

#include "common/io/mesh_io_internal.h"

#define PLY_MAX_ELEMS 16
#define PLY_MAX_PROPS 64
#define PLY_MAX_TEXTURE 256

typedef enum ply_format { PLY_ASCII, PLY_BINARY_LE, PLY_BINARY_BE } ply_format;

typedef enum ply_type {
    PLY_I8,
    PLY_U8,
    PLY_I16,
    PLY_U16,
    PLY_I32,
    PLY_U32,
    PLY_F32,
    PLY_F64
} ply_type;

/* What the reader takes from a property; PLY_ROLE_NONE is read and skipped. The names are those
 * assimp's PLY reader knew (x, nx, red or r, u or s or texture_u, ...), so files it read still
 * read the same. */
typedef enum ply_role {
    PLY_ROLE_NONE,
    PLY_ROLE_X,
    PLY_ROLE_Y,
    PLY_ROLE_Z,
    PLY_ROLE_NX,
    PLY_ROLE_NY,
    PLY_ROLE_NZ,
    PLY_ROLE_RED,
    PLY_ROLE_GREEN,
    PLY_ROLE_BLUE,
    PLY_ROLE_ALPHA,
    PLY_ROLE_U,
    PLY_ROLE_V,
    PLY_ROLE_INDICES, /* a face's vertex list, or a triangle strip (-1 restarts it) */
    PLY_ROLE_COUNT_
} ply_role;

typedef enum ply_kind { PLY_ELEM_OTHER, PLY_ELEM_VERTEX, PLY_ELEM_FACE, PLY_ELEM_STRIP } ply_kind;

typedef struct ply_prop {
    uint8_t is_list;
    uint8_t count_type; /* ply_type of a list's length (an integer type) */
    uint8_t type;       /* ply_type of the value, or of a list's items */
    uint8_t role;       /* ply_role */
} ply_prop;

typedef struct ply_elem {
    char name[32];
    uint8_t kind; /* ply_kind */
    uint64_t count;
    uint32_t n_props;
    ply_prop props[PLY_MAX_PROPS];
} ply_elem;

typedef struct ply_header {
    ply_format format;
    uint32_t n_elems;
    ply_elem elems[PLY_MAX_ELEMS];
    size_t body;                   /* offset of the first body byte */
    char texture[PLY_MAX_TEXTURE]; /* "comment TextureFile NAME": the diffuse texture, or "" */
} ply_header;

/* Bytes of a binary value of type t. */
size_t lm_ply_type_size(ply_type t);

/* Parse the header of d[0, size) into h: exactly one format line, at most one vertex, face and
 * tristrips element each, known types, lists counted by integers; each element's count within
 * the limits (faces and strips: max_tris; others: LM_MESH_MAX_VERTS) and within the bytes after
 * the header (an element takes at least one byte, a property at least its binary size or two
 * ASCII characters), so nothing the header claims is allocated before the file shows it. One-line
 * errors naming `name`: LM_E_FORMAT (malformed), LM_E_RANGE (over a limit). */
lm_status lm_ply_header_parse(const uint8_t *d, size_t size, const char *name, uint32_t max_tris,
                              ply_header *h);

#endif
