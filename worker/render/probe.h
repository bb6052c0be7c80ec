/* worker/render/probe.h — the identity of a renderer, defined by what changes pixels.
 *
 * Two renderers may be mixed within a job only if they rasterise alike. The description string
 * is no guide (llvmpipe says "128 bits" or "256 bits" by LP_NATIVE_VECTOR_WIDTH and draws the same
 * pixels either way; two drivers may share a name and differ), so the identity is a fingerprint:
 * a probe scene — a few hundred triangles at sub-pixel positions, crossing and touching, with
 * per-corner colours and normals, a mipmapped texture sampled at several scales, depth ties —
 * rendered through the views backend exactly as a job renders (targets and a current mesh), its
 * images hashed. Equal fingerprints: the job accepts the worker; different: it is refused.
 * The probe's mesh and texture are made from integers only (no libm), the same on every host. */
#ifndef LM_WORKER_PROBE_H
#define LM_WORKER_PROBE_H

#include "common/error.h"
#include "proto/wire.h"

/* Render the probe on `device` ("auto", "host", "egl:N"): id gets LM_WIRE_RENDERER_ID_CHARS hex
 * digits and a NUL (id must hold 17 bytes), desc (128 bytes, may be NULL) the renderer's
 * description. */
lm_status wk_probe_renderer(const char *device, char *id, char *desc);

#endif
