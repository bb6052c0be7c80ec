/* proto/keys.h — CURVE keys for the coordinator and its workers (ZeroMQ's CurveZMQ: every frame
 * encrypted and authenticated, the coordinator's key checked by the workers, the workers' keys
 * checked by the coordinator against an allow-list through a ZAP handler).
 *
 * A key folder (`lumesh keygen -o DIR`) holds, as Z85 text:
 *   coordinator.key  "public KEY\nsecret KEY\n" (mode 0600)   coordinator.pub  "KEY\n"
 *   worker.key       the same for a worker (mode 0600)        worker.pub       "KEY\n"
 *   workers.allow    the worker public keys the coordinator accepts, one per line ('#' comments)
 * The coordinator reads coordinator.key and workers.allow; a worker reads worker.key and
 * coordinator.pub. More workers with keys of their own: add their public keys to workers.allow. */
#ifndef LM_PROTO_KEYS_H
#define LM_PROTO_KEYS_H

#include <stdint.h>

#include "common/error.h"

#define LM_KEY_Z85 40 /* characters of a key in Z85 */

typedef struct lm_keypair {
    char pub[LM_KEY_Z85 + 1], sec[LM_KEY_Z85 + 1];
} lm_keypair;

typedef struct lm_allow {
    uint8_t (*keys)[32]; /* binary public keys */
    uint32_t n;
} lm_allow;

/* A new key folder: fails (LM_E_IO) rather than overwrite keys already there. */
lm_status lm_keys_generate(const char *dir);

lm_status lm_keys_load_pair(const char *dir, const char *name, lm_keypair *out);
lm_status lm_keys_load_public(const char *dir, const char *name, char pub[LM_KEY_Z85 + 1]);
lm_status lm_keys_load_allow(const char *dir, lm_allow *out);
void lm_allow_free(lm_allow *a);
int lm_allow_has(const lm_allow *a, const uint8_t key[32]);

/* A worker's socket as a CURVE client of the coordinator whose keys are in dir. */
lm_status lm_keys_client(void *sock, const char *dir);
/* The coordinator's socket as a CURVE server with its keys from dir (the ZAP domain "lumesh"). */
lm_status lm_keys_server(void *sock, const char *dir);

#endif
