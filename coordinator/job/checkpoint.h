/* coordinator/job/checkpoint.h — checkpoint files: what lets a killed job continue to the same
 * result.
 *
 * A checkpoint is one file, all integers little-endian:
 *   "LUMESHCK" magic (8 bytes), u32 version, u32 key size,
 *   the job key (hash of the original file's bytes, hash of the --initial file's bytes or 0, seed,
 *   target vertex count, views, image size, optimised attributes, evaluations between regrid
 *   draws, the views' distribution (lm_view_dist, u32, then 4 zero bytes) and the hash of the
 *   camera file's cameras (co_checkpoint_hash_cameras; 0 without one)), u64 payload length, the
 * payload (the job's: the regrid draw in force, u32, then the optimizer's own serialisation), and a
 * u64 FNV-1a checksum of every byte before it. Writes are atomic: the whole file is assembled in
 * memory, written to a temporary file in the same folder, flushed, fsync'ed, renamed over the old
 * one, and the folder is fsync'ed; a failure at any point leaves the previous checkpoint as it was.
 * Reads verify magic, version, length, checksum and key before handing the payload to the loader,
 * and name the first problem in one line. Version 2 (a 48-byte key: no distribution, no camera
 * hash) is still read, as sphere views without cameras. Version 4 (an 80-byte key: version 3's,
 * then u64 evaluations between validation checks, u32 validation views, u32 plateau patience) is
 * written only by a job that validates (its payload then also holds the training views' epoch and
 * the validation state: coordinator/job/job.c); every other job writes version 3 as before, and
 * versions 2 and 3 read as jobs without validation. Version 5 (a 96-byte key: version 4's, then
 * u32 view schedule, 4 zero bytes, u64 the evaluations its stages are fractions of) is written only
 * by a job with `--view-schedule grow` (its payload then also holds the stage, after the epoch's
 * place); versions 2 to 4 read as jobs with fixed views. */
#ifndef LM_COORDINATOR_CHECKPOINT_H
#define LM_COORDINATOR_CHECKPOINT_H

#include <stdint.h>
#include <stdio.h>

#include "common/error.h"
#include "common/view.h"

#define CO_CHECKPOINT_VERSION 5u
/* Refuse to read checkpoints larger than this (a corrupted length must not allocate terabytes). */
#define CO_CHECKPOINT_MAX_BYTES ((uint64_t)1 << 34)

/* The job options a checkpoint is only valid for. */
typedef struct co_checkpoint_key {
    uint64_t original_hash; /* co_checkpoint_hash_file() of the original model file */
    uint64_t initial_hash;  /* same for the --initial file; 0 when the coarse mesh came from QEM,
                               CO_CHECKPOINT_IMAGE_START from the image-driven simplification,
                               CO_CHECKPOINT_ADAPTIVE_START from the shape-adaptive one */
    uint64_t seed;
    uint32_t target_verts; /* resolved target of the initial simplification; 0 with --initial */
    uint32_t views;
    uint32_t size;
    uint32_t attrs;             /* LM_ATTR_* optimised besides positions */
    uint64_t regrid_every;      /* evaluations between the views' regrid draws; 0 = never */
    uint32_t view_dist;         /* lm_view_dist: sphere, upper hemisphere or a camera file */
    uint64_t cameras_hash;      /* co_checkpoint_hash_cameras of the views */
    uint64_t validate_every;    /* evaluations between validation checks; 0 = none (version 3) */
    uint32_t validate_views;    /* the validation views' count (0 without validation) */
    uint32_t validate_patience; /* checks without a new best before new training views */
    uint32_t view_schedule;     /* 0: fixed views; co_view_schedule grow or extend (version 5) */
    uint64_t schedule_evals; /* the budget the grow schedule's stages are fractions of (else 0) */
} co_checkpoint_key;

/* initial_hash of a job that started from the image-driven simplification ("image-v1"). */
#define CO_CHECKPOINT_IMAGE_START 0x696d6167652d7631ull
/* initial_hash of a job that started from the shape-adaptive simplification ("adapt-v1"). */
#define CO_CHECKPOINT_ADAPTIVE_START 0x61646170742d7631ull

/* Writes the payload to fp (a memory stream); returns LM_OK or an error (nothing is written then).
 */
typedef lm_status (*co_checkpoint_save_fn)(const void *ctx, FILE *fp);
/* Reads the payload from fp (a memory stream over exactly the payload bytes). */
typedef lm_status (*co_checkpoint_load_fn)(void *ctx, FILE *fp);

/* 64-bit FNV-1a of a file's bytes; LM_E_IO naming the file when it cannot be read. */
lm_status co_checkpoint_hash_file(const char *path, uint64_t *out);
/* 64-bit FNV-1a of a buffer, continuing from `h` (start with CO_FNV_OFFSET). */
#define CO_FNV_OFFSET 0xcbf29ce484222325ull
uint64_t co_fnv1a(uint64_t h, const void *data, size_t n);

/* 64-bit FNV-1a of the cameras' numbers as parsed (each float's bits, little-endian: position,
 * target, up, fov), so a reformatted file with the same cameras resumes; 0 for views without
 * cameras. */
uint64_t co_checkpoint_hash_cameras(const lm_view_spec *views);

/* Atomically replace `path` with a checkpoint of `key` and the payload `save` produces. */
lm_status co_checkpoint_write(const char *path, const co_checkpoint_key *key,
                              co_checkpoint_save_fn save, const void *ctx);

/* Verify `path` against `expect` and feed its payload to `load`. Errors (one line, naming the
 * file): LM_E_IO unreadable; LM_E_FORMAT not a checkpoint, other version, truncated, corrupted, or
 * payload not fully consumed; LM_E_INVALID written for another original or other options (names
 * which). */
lm_status co_checkpoint_read(const char *path, const co_checkpoint_key *expect,
                             co_checkpoint_load_fn load, void *ctx);

/* Only the checks of co_checkpoint_read (file, frame, checksum, key): lets a job refuse a bad
 * --resume before it spends time rendering. */
lm_status co_checkpoint_verify(const char *path, const co_checkpoint_key *expect);

#endif
