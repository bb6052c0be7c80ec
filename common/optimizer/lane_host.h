/* common/optimizer/lane_host.h — an isolated lane (lanes.h) run away from the optimizer object:
 * what a worker holding a mesh replica at the group's start and a complete set of views would do
 * for "optimise lane i of group g". Given a request (lane_work.h) it optimises the edge
 * (lm_edge_optimise with an isolated context) on its own copy of the mesh, prices every
 * evaluation against the views as they are (the group's start: nothing is committed to them) and
 * fills a result that the optimizer's merge takes as it takes an in-process lane's. One host runs
 * any number of lanes, one after the other; nothing of one carries over to the next. */
#ifndef LM_COMMON_OPTIMIZER_LANE_HOST_H
#define LM_COMMON_OPTIMIZER_LANE_HOST_H

#include "common/optimizer/lane_work.h"
#include "common/optimizer/moves.h"
#include "common/views_api.h"

typedef struct lm_lane_host lm_lane_host;

/* cfg: the job's moves config (the optimizer's moves_cfg). */
lm_status lm_lane_host_create(const lm_moves_config *cfg, lm_lane_host **out);
void lm_lane_host_destroy(lm_lane_host *h);

/* Run the lane of req on a copy of start (the group's start mesh) against views (committed to
 * start, left so); res is cleared and filled. A failure of the lane's run is in res->status (and
 * returned). token names start and req's queue: while a caller gives the same nonzero token, start
 * is the same mesh, unchanged, and req->queue the same entries, so the host derives the start's
 * triangle records and the queue's heap once for all those lanes (a copy of the kept queue is the
 * rebuilt one: its pop order depends only on its entries). A caller gives a token never given
 * before whenever either changes; 0 keeps nothing. The result does not depend on the token. */
lm_status lm_lane_host_run(lm_lane_host *h, const lm_mesh *start, lm_views *views,
                           const lm_lane_request *req, uint64_t token, lm_lane_result *res);

#endif
