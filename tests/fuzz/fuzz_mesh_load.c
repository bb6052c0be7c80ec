/* tests/fuzz/fuzz_mesh_load.c — libFuzzer target for model loading (lm_mesh_load_memory): the
 * first byte picks the format hint, the rest is the file. Any input must give LM_OK with a valid
 * mesh, or an error status with a one-line message; never a crash, a leak or a hang.
 * glTF, GLB, FBX and DAE are read in a reader process in the product (common/io/mesh_io_isolate.c:
 * this program run afresh), a process start per input: 5-10 runs a second. So unpinned (the test
 * gate's fixed runs) those inputs go through the guards in front of that process only, the part
 * that runs in the caller; pinned to one of them (the campaigns), through the whole product path,
 * where a crash inside assimp is an error status and what this target catches are faults of the
 * guards, the hand-back and the caller's side (libFuzzer does not see the reader's coverage).
 * test_mesh_io_isolate and integration_cli load the crashing inputs through the whole path.
 * PLY is read by lumesh's own reader (common/io/mesh_io_ply_read.c), the other formats by assimp.
 * LUMESH_FUZZ_FORMAT=ply (or obj, off, ...) pins every input to one format, the first byte still
 * skipped, for the per-format campaigns of scripts/fuzz-explore.sh.
 * Seeds: tests/fuzz/corpus/mesh_load/ (tiny OBJ, PLY, OFF, STL, glTF, GLB, DAE and FBX files, and
 * every finding as a regress_* input). */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/io/mesh_io.h"
#include "common/io/mesh_io_internal.h"
#include "common/log.h"

/* assimp 5.2 leaks the mesh it was building when one of its readers throws part-way (its ASCII
 * STL reader on a facet cut short, for one): those are assimp's, not findings of this target.
 * (Leaks of scenes we fail to release are covered by the unit tests under valgrind.) */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void)
{
    return "leak:libassimp.so\n";
}

static const char *const exts[] = {"obj", "ply", "off", "stl", "gltf", "glb", "dae", "fbx"};

static const char *pinned; /* LUMESH_FUZZ_FORMAT, or NULL */

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    const char *f = getenv("LUMESH_FUZZ_FORMAT");
    for (size_t i = 0; f && *f && i < sizeof exts / sizeof exts[0]; i++)
        if (!strcmp(f, exts[i]))
            pinned = exts[i];
    if (f && *f && !pinned) {
        fprintf(stderr,
                "fuzz_mesh_load: LUMESH_FUZZ_FORMAT=%s is not one of obj ply off stl gltf "
                "glb dae fbx\n",
                f);
        exit(2);
    }
    return 0;
}

/* The guards that run in the caller before a reader process is started: an error in one line or
 * LM_OK, never a crash. The bytes get a NUL after them, as lm_mesh_load_memory gives them. */
static int guard_only(const uint8_t *data, size_t size, const char *ext, uint32_t max_tris)
{
    uint8_t *copy = malloc(size + 1);
    if (!copy)
        return 0;
    memcpy(copy, data, size);
    copy[size] = 0;
    char name[32];
    snprintf(name, sizeof name, "memory.%s", ext);
    lm_status s = lm_io_guard(copy, size, ext, name, max_tris);
    LM_ASSERT(s == LM_OK || (lm_last_error()[0] != '\0' && !strchr(lm_last_error(), '\n')));
    free(copy);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    lm_log_set_level(LM_LOG_ERROR); /* dropped-triangle and texture warnings are expected */
    lm_load_options opts = {.max_tris = 1u << 20};
    const char *ext = pinned ? pinned : exts[data[0] % 8];
    if (!pinned && lm_io_isolated_format(ext))
        return guard_only(data + 1, size - 1, ext, opts.max_tris);
    lm_mesh *m = NULL;
    lm_status s = lm_mesh_load_memory(data + 1, size - 1, ext, &opts, &m);
    if (s == LM_OK) {
        LM_ASSERT(m != NULL && m->live_tris > 0 && m->live_tris <= opts.max_tris);
        LM_ASSERT(lm_mesh_validate(m) == LM_OK);
        lm_mesh_destroy(m);
    } else {
        LM_ASSERT(m == NULL && lm_last_error()[0] != '\0' && !strchr(lm_last_error(), '\n'));
    }
    return 0;
}
