/* tests/fuzz/fuzz_mesh_load.c — libFuzzer target for model loading (lm_mesh_load_memory): the
 * first byte picks the format hint, the rest is the file. Any input must give LM_OK with a valid
 * mesh, or an error status with a one-line message; never a crash, a leak or a hang.
 * glTF, GLB, FBX and DAE inputs are read in a reader process (common/io/mesh_io_isolate.c: this
 * fuzzer's own binary run afresh), as in the product: a crash inside assimp's readers for them is
 * an error status here, and what this target catches for them are faults of our guards, the
 * hand-back and the caller's side (libFuzzer does not see the reader process's coverage).
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

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    lm_log_set_level(LM_LOG_ERROR); /* dropped-triangle and texture warnings are expected */
    lm_load_options opts = {.max_tris = 1u << 20};
    lm_mesh *m = NULL;
    lm_status s =
        lm_mesh_load_memory(data + 1, size - 1, pinned ? pinned : exts[data[0] % 8], &opts, &m);
    if (s == LM_OK) {
        LM_ASSERT(m != NULL && m->live_tris > 0 && m->live_tris <= opts.max_tris);
        LM_ASSERT(lm_mesh_validate(m) == LM_OK);
        lm_mesh_destroy(m);
    } else {
        LM_ASSERT(m == NULL && lm_last_error()[0] != '\0' && !strchr(lm_last_error(), '\n'));
    }
    return 0;
}
