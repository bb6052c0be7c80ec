/* coordinator/quality/report_levels.c — the report of a level-of-detail set: the levels of a
 * lods.json (coordinator/simplify/lod_manifest.h) loaded as the report's models "LOD0",
 * "LOD1", ... after the original, each with the switch distance the manifest gives it. Level
 * files are resolved against the manifest's folder; a manifest of one MSFT_lod GLB is refused
 * (its levels have no files of their own). */
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "coordinator/quality/report_internal.h"

/* path as the manifest at `manifest` names it: absolute as it is, else beside the manifest. */
static char *resolve(const char *manifest, const char *path)
{
    const char *slash = strrchr(manifest, '/');
    size_t dir = path[0] == '/' || !slash ? 0 : (size_t)(slash - manifest) + 1;
    char *out = malloc(dir + strlen(path) + 1);
    if (out) {
        memcpy(out, manifest, dir);
        strcpy(out + dir, path);
    }
    return out;
}

static lm_status bad(const char *manifest, const char *what)
{
    return lm_fail(LM_E_FORMAT, "level manifest '%s': %s", manifest, what);
}

/* Level k of the manifest into m: its file loaded, its label and switch distance. */
static lm_status load_level(co_report_model *m, const char *manifest, json_t *level, uint32_t k)
{
    json_t *file = json_object_get(level, "file");
    json_t *dist = json_object_get(json_object_get(level, "switch"), "distance");
    char what[96];
    snprintf(what, sizeof what, "level %u has no \"file\"", k);
    if (!json_is_string(file))
        return bad(manifest, what);
    if (json_object_get(level, "node"))
        return bad(manifest, "its levels are nodes of one MSFT_lod GLB; the report needs one "
                             "file per level (lumesh lod without --msft-lod)");
    snprintf(m->level_label, sizeof m->level_label, "LOD%u", k);
    m->level_path = resolve(manifest, json_string_value(file));
    if (!m->level_path)
        return lm_fail(LM_E_NOMEM, "out of memory for a level's path");
    lm_status s = co_report_load_model(m, m->level_label, m->level_path);
    if (!s && json_is_number(dist))
        m->switch_distance = json_number_value(dist);
    return s;
}

lm_status co_report_load_levels(co_report *r)
{
    const char *path = r->o->lods;
    json_error_t err;
    json_t *root = json_load_file(path, JSON_REJECT_DUPLICATES, &err);
    if (!root)
        return lm_fail(LM_E_FORMAT, "level manifest '%s': not readable JSON (line %d: %s)", path,
                       err.line, err.text);
    json_t *levels = json_object_get(root, "levels");
    size_t n = json_array_size(levels);
    lm_status s = LM_OK;
    if (n == 0)
        s = bad(path, "no \"levels\"");
    else if (n > CO_REPORT_MAX_MODELS - 1) {
        char what[64];
        snprintf(what, sizeof what, "%zu levels, at most %d", n, LM_MESH_MAX_LODS);
        s = bad(path, what);
    }
    r->levels = 1;
    if (!s)
        s = co_report_load_model(&r->model[0], "original", r->o->original);
    r->n_models = 1;
    for (size_t k = 0; !s && k < n; k++)
        s = load_level(&r->model[r->n_models++], path, json_array_get(levels, k), (uint32_t)k);
    json_decref(root);
    return s;
}
