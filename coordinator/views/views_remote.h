/* coordinator/views/views_remote.h — the views served by lumesh-worker processes of a pool
 * (coordinator/pool/pool.h), made by co_views_create for CO_VIEWS_REMOTE. Not for other callers.
 *
 * Layout: the views are dealt into G = min(workers, views) shares, every G-th view from the k-th
 * (common/view.h, lm_view_deal: each share sees the model from all sides, so a patch's work
 * splits evenly); worker i serves share i mod G (workers beyond the first G are replicas: a batch
 * of patches is divided between the replicas of a share). Every worker receives every change of
 * state, tagged with its sequence number; the backend keeps the current state (materials, a replica
 * of the mesh) to re-send it to a worker that answers Stale or joins later. Results are exact int64
 * sums over the shares, so they are the same for any number of workers and any layout.
 *
 * Workers that join are brought in at the next operation (assets they lack, the job, their views,
 * the state); lost ones are left out and the operation is done again without them; with no worker
 * the job waits, saying so, until one comes. With whole views (co_views_desc.whole) and two or
 * more workers to bring up, their targets are rendered once, split over them (a share each, read
 * back and shipped to all as one targets asset, proto/asset.h), and each is assigned all views with
 * that asset instead of rendering them all (views_remote_layout.c; with audits on, one view of
 * each share is drawn again by another worker and compared first; any loss, mismatch or failure on
 * the way: each renders them all, as with one worker). A worker's Failure ends the operation with
 * its message (a request a worker refuses is a bug, not a fault to hide). */
#ifndef LM_COORDINATOR_VIEWS_VIEWS_REMOTE_H
#define LM_COORDINATOR_VIEWS_VIEWS_REMOTE_H

#include "coordinator/views/views.h"

lm_status co_views_remote_create(const co_views_desc *d, lm_views **out);

#endif
