/* common/io/camera_file.c — reading camera files (see camera_file.h) with jansson. */
#include "common/io/camera_file.h"

#include <errno.h>
#include <jansson.h>
#include <stdlib.h>
#include <string.h>

#include "common/bytes.h"
#include "common/io/camera_gltf.h"

static lm_status bad(const char *name, uint32_t i, const char *what)
{
    return lm_fail(LM_E_FORMAT, "camera file '%s': camera %u: %s", name, i, what);
}

/* An array of 3 finite numbers. */
static lm_status read_vec3(json_t *cam, const char *key, const char *name, uint32_t i, float v[3])
{
    json_t *a = json_object_get(cam, key);
    if (!a)
        return lm_fail(LM_E_FORMAT, "camera file '%s': camera %u: missing \"%s\"", name, i, key);
    if (!json_is_array(a) || json_array_size(a) != 3)
        return lm_fail(LM_E_FORMAT, "camera file '%s': camera %u: \"%s\" is not 3 numbers", name, i,
                       key);
    for (size_t k = 0; k < 3; k++) {
        json_t *x = json_array_get(a, k);
        if (!json_is_number(x))
            return lm_fail(LM_E_FORMAT, "camera file '%s': camera %u: \"%s\" is not 3 numbers",
                           name, i, key);
        v[k] = (float)json_number_value(x);
    }
    return LM_OK;
}

static lm_status read_camera(json_t *cam, const char *name, uint32_t i, lm_camera *c)
{
    if (!json_is_object(cam))
        return bad(name, i, "not an object");
    const char *key;
    json_t *val;
    json_object_foreach(cam, key, val)
    {
        if (!strcmp(key, "weight"))
            return bad(name, i, "\"weight\" is not supported (views are weighted equally)");
        if (strcmp(key, "position") && strcmp(key, "target") && strcmp(key, "up") &&
            strcmp(key, "fov") && strcmp(key, "name"))
            return lm_fail(LM_E_FORMAT, "camera file '%s': camera %u: unknown key \"%s\"", name, i,
                           key);
    }
    lm_status st = read_vec3(cam, "position", name, i, c->position);
    if (st == LM_OK)
        st = read_vec3(cam, "target", name, i, c->target);
    if (st == LM_OK)
        st = read_vec3(cam, "up", name, i, c->up);
    if (st != LM_OK)
        return st;
    json_t *fov = json_object_get(cam, "fov");
    if (!fov)
        return bad(name, i, "missing \"fov\"");
    if (!json_is_number(fov))
        return bad(name, i, "\"fov\" is not a number");
    c->fov_deg = (float)json_number_value(fov);
    const char *why = lm_camera_problem(c);
    return why ? bad(name, i, why) : LM_OK;
}

lm_status lm_cameras_parse(const char *json, size_t len, const char *name, lm_camera *out,
                           uint32_t *n)
{
    if (lm_gltf_is_glb(json, len)) {
        lm_status st = lm_gltf_json_chunk(json, len, name, &json, &len);
        if (st != LM_OK)
            return st;
    }
    json_error_t err;
    /* jansson refuses NaN and Infinity literals; numbers too large for a double overflow */
    json_t *root = json_loadb(json, len, JSON_REJECT_DUPLICATES, &err);
    if (!root)
        return lm_fail(LM_E_FORMAT, "camera file '%s': not JSON (line %d: %s)", name, err.line,
                       err.text);
    if (json_is_object(root) && json_object_get(root, "asset")) {
        lm_status st = lm_gltf_cameras(root, name, out, n);
        json_decref(root);
        return st;
    }
    lm_status st = LM_OK;
    size_t count = json_is_array(root) ? json_array_size(root) : 0;
    if (!json_is_array(root))
        st = lm_fail(LM_E_FORMAT, "camera file '%s': expected an array of cameras", name);
    else if (count == 0)
        st = lm_fail(LM_E_FORMAT, "camera file '%s': no cameras", name);
    else if (count > LM_MAX_VIEWS)
        st = lm_fail(LM_E_FORMAT, "camera file '%s': %zu cameras, at most %d", name, count,
                     LM_MAX_VIEWS);
    for (size_t i = 0; st == LM_OK && i < count; i++)
        st = read_camera(json_array_get(root, i), name, (uint32_t)i, &out[i]);
    json_decref(root);
    if (st == LM_OK)
        *n = (uint32_t)count;
    return st;
}

/* How many bytes of the file to read: a binary glTF's header and JSON chunk, else all of it (one
 * more than the cap, to tell a file over it). */
static size_t bytes_wanted(FILE *fp, size_t cap)
{
    char head[20];
    size_t got = fread(head, 1, sizeof head, fp);
    rewind(fp);
    if (got == sizeof head && lm_gltf_is_glb(head, got)) {
        uint32_t chunk = lm_le32(head + 12);
        return (size_t)chunk + sizeof head <= cap ? (size_t)chunk + sizeof head : cap + 1;
    }
    return cap + 1;
}

lm_status lm_cameras_read(const char *path, lm_camera *out, uint32_t *n)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return lm_fail(LM_E_IO, "cannot read camera file '%s': %s", path, strerror(errno));
    enum { CAP = 64 << 20 }; /* a glTF's JSON with its buffers inlined as base64 */
    size_t want = bytes_wanted(fp, CAP);
    char *buf = malloc(want);
    size_t len = buf ? fread(buf, 1, want, fp) : 0;
    int failed = ferror(fp);
    fclose(fp);
    lm_status st = !buf     ? lm_fail(LM_E_NOMEM, "out of memory for camera file '%s'", path)
                   : failed ? lm_fail(LM_E_IO, "cannot read camera file '%s'", path)
                   : len > CAP
                       ? lm_fail(LM_E_FORMAT, "camera file '%s' is larger than 64 MiB", path)
                       : lm_cameras_parse(buf, len, path, out, n);
    free(buf);
    return st;
}
