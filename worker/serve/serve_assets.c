/* worker/serve/serve_assets.c — the worker's side of shipping assets: an Offer is answered with the
 * hashes it lacks (Need) or Ready; Asset chunks are gathered in order, checked against their hash
 * when complete and kept in the cache (across jobs); Ready goes out when the offer is complete. */
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"

#include "worker/serve/serve_internal.h"

static wk_upload *find_upload(wk_server *s, const lm_asset_hash *h)
{
    for (uint32_t i = 0; i < s->n_up; i++)
        if (!memcmp(s->up[i].hash.b, h->b, sizeof h->b))
            return &s->up[i];
    return NULL;
}

static lm_status hash_of(const ProtobufCBinaryData *b, lm_asset_hash *h)
{
    if (b->len != LM_ASSET_HASH_BYTES)
        return lm_fail(LM_E_FORMAT, "an asset hash of %zu bytes (not %d)", b->len,
                       LM_ASSET_HASH_BYTES);
    memcpy(h->b, b->data, sizeof h->b);
    return LM_OK;
}

static lm_status add_upload(wk_server *s, const lm_asset_hash *h)
{
    if (s->n_up == s->cap_up && !LM_GROW32(&s->up, &s->cap_up, (size_t)s->n_up + 1, 8))
        return lm_fail(LM_E_NOMEM, "out of memory for uploads");
    s->up[s->n_up++] = (wk_upload){.hash = *h};
    return LM_OK;
}

/* Forget the uploads in progress (their chunks so far are freed). */
static void drop_uploads(wk_server *s)
{
    for (uint32_t i = 0; i < s->n_up; i++)
        free(s->up[i].data);
    s->n_up = 0;
    s->offer_req = 0;
}

lm_status wk_serve_offer(wk_server *s, const lm_msg *m)
{
    const Lumesh__Offer *o = m->offer;
    /* An offer starts the exchange over. An upload of an earlier offer that never completed (the
     * coordinator gave this worker up mid-transfer, then took it back as a new worker) would
     * otherwise be neither asked for nor sent again, and Ready would never go out. */
    drop_uploads(s);
    lm_asset_hash *missing = malloc((o->n_assets + 1) * sizeof *missing);
    if (!missing)
        return wk_serve_fail(s, m->req, LM_E_NOMEM, "out of memory for an offer");
    uint32_t n = 0;
    lm_status st = LM_OK;
    for (size_t i = 0; i < o->n_assets && st == LM_OK; i++) {
        lm_asset_hash h;
        st = hash_of(&o->assets[i], &h);
        if (st == LM_OK && !lm_asset_set_find(&s->cache, &h) && !find_upload(s, &h)) {
            missing[n++] = h;
            st = add_upload(s, &h);
        }
    }
    if (st != LM_OK) {
        free(missing);
        return wk_serve_fail(s, m->req, st, lm_last_error());
    }
    s->offer_req = m->req;
    if (s->n_up == 0) {
        free(missing);
        Lumesh__Ready r = LUMESH__READY__INIT;
        s->offer_req = 0;
        return wk_serve_send(s, m->req, LUMESH__MSG__BODY_READY, &r);
    }
    ProtobufCBinaryData *list = malloc(n * sizeof *list);
    if (!list) {
        free(missing);
        return wk_serve_fail(s, m->req, LM_E_NOMEM, "out of memory for an offer");
    }
    for (uint32_t i = 0; i < n; i++)
        list[i] = (ProtobufCBinaryData){LM_ASSET_HASH_BYTES, missing[i].b};
    Lumesh__Need need = LUMESH__NEED__INIT;
    need.n_assets = n;
    need.assets = list;
    st = wk_serve_send(s, m->req, LUMESH__MSG__BODY_NEED, &need);
    free(list);
    free(missing);
    return st;
}

/* A finished upload: its bytes must hash to its name. */
static lm_status complete(wk_server *s, wk_upload *u)
{
    lm_asset_hash h;
    lm_status st = LM_OK;
    char a[17], b[17];
    lm_asset_hash_of(u->data, u->size, &h);
    if (memcmp(h.b, u->hash.b, sizeof h.b)) {
        free(u->data);
        st = lm_fail(LM_E_FORMAT, "asset %s arrived with the content of %s",
                     lm_asset_hash_short(&u->hash, a), lm_asset_hash_short(&h, b));
    } else {
        st = lm_asset_set_put(&s->cache, u->data, u->size, NULL);
    }
    *u = s->up[--s->n_up];
    return st;
}

static lm_status take_chunk(wk_upload *u, const Lumesh__Asset *a)
{
    if (!u->data) {
        if (a->size == 0 || a->size > LM_ASSET_MAX_BYTES)
            return lm_fail(LM_E_RANGE, "an asset of %llu bytes", (unsigned long long)a->size);
        u->data = malloc(a->size);
        if (!u->data)
            return lm_fail(LM_E_NOMEM, "out of memory for an asset of %llu bytes",
                           (unsigned long long)a->size);
        u->size = a->size;
    }
    if (a->size != u->size || a->offset != u->got || a->data.len > u->size - u->got)
        return lm_fail(LM_E_FORMAT, "asset chunk at %llu of %zu bytes does not follow %zu of %zu",
                       (unsigned long long)a->offset, a->data.len, u->got, u->size);
    memcpy(u->data + u->got, a->data.data, a->data.len);
    u->got += a->data.len;
    return LM_OK;
}

lm_status wk_serve_asset(wk_server *s, const lm_msg *m)
{
    lm_asset_hash h;
    lm_status st = hash_of(&m->asset->hash, &h);
    wk_upload *u = st == LM_OK ? find_upload(s, &h) : NULL;
    if (st == LM_OK && !u)
        st = lm_fail(LM_E_INVALID, "an asset that was not offered");
    if (st == LM_OK)
        st = take_chunk(u, m->asset);
    if (st == LM_OK && u->got == u->size)
        st = complete(s, u);
    else if (st != LM_OK && u) {
        free(u->data);
        *u = s->up[--s->n_up];
    }
    if (st != LM_OK)
        return wk_serve_fail(s, m->req, st, lm_last_error());
    if (s->n_up == 0 && s->offer_req) {
        Lumesh__Ready r = LUMESH__READY__INIT;
        uint64_t req = s->offer_req;
        s->offer_req = 0;
        return wk_serve_send(s, req, LUMESH__MSG__BODY_READY, &r);
    }
    return LM_OK;
}

void wk_serve_assets_free(wk_server *s)
{
    drop_uploads(s);
    free(s->up);
    s->up = NULL;
    s->n_up = s->cap_up = 0;
    lm_asset_set_free(&s->cache);
}
