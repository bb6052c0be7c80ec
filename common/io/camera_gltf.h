/* common/io/camera_gltf.h — the cameras of a glTF 2.0 file (`--views-from model.gltf|.glb`): every
 * node of the default scene (else of every root node) that names a perspective camera, in
 * depth-first order of the node tree, becomes one lm_camera: its position is the node's world
 * translation, it looks down the node's world -Z with +Y up (glTF 2.0 §3.10), and its field of
 * view is the camera's yfov. The aspect ratio is not kept (lumesh's images are square).
 * Orthographic cameras are left out with a warning. Only the JSON is read: a .glb's binary chunk
 * is never looked at. */
#ifndef LM_COMMON_IO_CAMERA_GLTF_H
#define LM_COMMON_IO_CAMERA_GLTF_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/view.h"

/* Whether `len` bytes start like a binary glTF (the "glTF" magic). */
int lm_gltf_is_glb(const char *bytes, size_t len);

/* The JSON chunk of a binary glTF: *json points into bytes, *json_len its length. LM_E_FORMAT (one
 * line naming `name`) for a version other than 2, a truncated header or a first chunk that is not
 * JSON or runs past the end. */
lm_status lm_gltf_json_chunk(const char *bytes, size_t len, const char *name, const char **json,
                             size_t *json_len);

/* The cameras of a parsed glTF document (a jansson json_t *, passed as void * to keep jansson out
 * of this header) into out[0..*n), at most LM_MAX_VIEWS. LM_E_FORMAT (one line naming `name`): no
 * perspective camera node, more than LM_MAX_VIEWS, a node reached twice, a malformed node,
 * transform or camera, a camera lm_camera_problem refuses. */
lm_status lm_gltf_cameras(const void *root, const char *name, lm_camera *out, uint32_t *n);

#endif
