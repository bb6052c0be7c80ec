/* coordinator/pool/status.h — asking a running coordinator how its pool stands, as any peer may
 * (`lumesh workers --connect ADDR`): one Status request on a DEALER of our own, the StatusResult
 * back. With keys (the folder a worker uses), the connection is CURVE like a worker's. */
#ifndef LM_COORDINATOR_POOL_STATUS_H
#define LM_COORDINATOR_POOL_STATUS_H

#include "common/error.h"
#include "proto/wire.h"

/* out->msg holds the StatusResult on success (free with lm_wire_in_free); LM_E_IO when the
 * coordinator does not answer within timeout_s. */
lm_status co_pool_status_query(const char *endpoint, const char *keys, double timeout_s,
                               lm_wire_in *out);

#endif
