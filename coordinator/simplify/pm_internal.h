/* coordinator/simplify/pm_internal.h — what the progressive-mesh files share between their
 * writer (pm_write.c) and reader (pm_read.c): the magic words, the limits a reader enforces, and
 * the recorder's splits. Not for other folders. */
#ifndef LM_COORDINATOR_SIMPLIFY_PM_INTERNAL_H
#define LM_COORDINATOR_SIMPLIFY_PM_INTERNAL_H

#include "coordinator/simplify/pm.h"

#define CO_PM_MAGIC "LMPM"
#define CO_PM_END "LMPE"
#define CO_PM_MAX_STRING 4096 /* names and texture paths */
#define CO_PM_MAX_MATERIALS 65536
#define CO_PM_MAX_TEXTURE_PIXELS (1u << 26)
#define CO_PM_MAX_TEXTURE_SIDE 16384

/* Bytes of one element record in the file: id, alive, then the data. */
#define CO_PM_VERT_BYTES (4 + 4 + 12)
#define CO_PM_WEDGE_BYTES (4 + 4 + 4 + 36)
#define CO_PM_TRI_BYTES (4 + 4 + 20)

/* The i-th split in collapse order. */
const co_pm_split *co_pm_recorder_at(const co_pm_recorder *r, uint32_t i);

#endif
