/* common/io/camera_file.h — camera files (`--views-from FILE`): a JSON array of cameras, each an
 * object with "position", "target" and "up" (arrays of 3 numbers) and "fov" (the vertical field
 * of view in degrees, in (0, 180)); "name" is allowed and ignored. Every other key is refused,
 * "weight" included (views are weighted equally: coordinator/cli/COMMANDS.md says why). A glTF
 * 2.0 file (JSON with an "asset" object, or a binary .glb) gives its cameras (camera_gltf.h). */
#ifndef LM_COMMON_IO_CAMERA_FILE_H
#define LM_COMMON_IO_CAMERA_FILE_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/view.h"

/* Parse `len` bytes of JSON (`name` for the messages) into out[0..*n), at most LM_MAX_VIEWS
 * cameras. Errors (LM_E_FORMAT, one line naming `name` and the camera): not JSON, not an array,
 * empty, more than LM_MAX_VIEWS cameras, a missing or malformed field, an unknown key, a camera
 * lm_camera_problem refuses. */
lm_status lm_cameras_parse(const char *json, size_t len, const char *name, lm_camera *out,
                           uint32_t *n);

/* The same from a file (LM_E_IO when it cannot be read). */
lm_status lm_cameras_read(const char *path, lm_camera *out, uint32_t *n);

#endif
