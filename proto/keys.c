/* proto/keys.c — CURVE key folders: generating them (zmq_curve_keypair), reading them back, the
 * allow-list, and the socket options of a CURVE client and server. */
#include "proto/keys.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zmq.h>

static void path_of(char *buf, size_t cap, const char *dir, const char *name)
{
    snprintf(buf, cap, "%s/%s", dir, name);
}

/* Write text to dir/name (mode), refusing to replace a file that is there. */
static lm_status write_new(const char *dir, const char *name, const char *text, mode_t mode)
{
    char path[4096];
    path_of(path, sizeof path, dir, name);
    int fd = open(path, O_WRONLY | O_CREAT | O_EXCL, mode);
    if (fd < 0)
        return lm_fail(LM_E_IO, "cannot write %s: %s", path, strerror(errno));
    size_t n = strlen(text);
    ssize_t w = write(fd, text, n);
    int closed = close(fd);
    if (w != (ssize_t)n || closed != 0)
        return lm_fail(LM_E_IO, "cannot write %s: %s", path, strerror(errno));
    return LM_OK;
}

static lm_status new_pair(const char *dir, const char *name)
{
    char pub[LM_KEY_Z85 + 1], sec[LM_KEY_Z85 + 1], text[128], file[64];
    if (zmq_curve_keypair(pub, sec) != 0)
        return lm_fail(LM_E_UNSUPPORTED, "this ZeroMQ has no CURVE: %s", zmq_strerror(zmq_errno()));
    snprintf(text, sizeof text, "public %s\nsecret %s\n", pub, sec);
    snprintf(file, sizeof file, "%s.key", name);
    lm_status st = write_new(dir, file, text, 0600);
    snprintf(text, sizeof text, "%s\n", pub);
    snprintf(file, sizeof file, "%s.pub", name);
    if (st == LM_OK)
        st = write_new(dir, file, text, 0644);
    if (st == LM_OK && !strcmp(name, "worker")) {
        snprintf(text, sizeof text, "# worker public keys the coordinator accepts\n%s\n", pub);
        st = write_new(dir, "workers.allow", text, 0644);
    }
    return st;
}

lm_status lm_keys_generate(const char *dir)
{
    if ((mkdir(dir, 0700) != 0 && errno != EEXIST) || chmod(dir, 0700) != 0)
        return lm_fail(LM_E_IO, "cannot make the key folder %s: %s", dir, strerror(errno));
    lm_status st = new_pair(dir, "coordinator");
    return st == LM_OK ? new_pair(dir, "worker") : st;
}

/* The file's contents (at most cap - 1 bytes, NUL-terminated). */
static lm_status read_small(const char *dir, const char *name, char *buf, size_t cap)
{
    char path[4096];
    path_of(path, sizeof path, dir, name);
    FILE *f = fopen(path, "rb");
    if (!f)
        return lm_fail(LM_E_IO, "cannot read %s: %s (make keys with lumesh keygen)", path,
                       strerror(errno));
    size_t n = fread(buf, 1, cap - 1, f);
    fclose(f);
    buf[n] = 0;
    return LM_OK;
}

/* A Z85 key at s (40 characters that decode), copied to out. */
static int take_key(const char *s, char out[LM_KEY_Z85 + 1])
{
    uint8_t bin[32];
    size_t n = strcspn(s, " \t\r\n");
    if (n != LM_KEY_Z85)
        return 0;
    memcpy(out, s, LM_KEY_Z85);
    out[LM_KEY_Z85] = 0;
    return zmq_z85_decode(bin, out) != NULL;
}

lm_status lm_keys_load_pair(const char *dir, const char *name, lm_keypair *out)
{
    char buf[512], file[64];
    snprintf(file, sizeof file, "%s.key", name);
    lm_status st = read_small(dir, file, buf, sizeof buf);
    if (st != LM_OK)
        return st;
    const char *p = strstr(buf, "public "), *q = strstr(buf, "secret ");
    if (!p || !q || !take_key(p + 7, out->pub) || !take_key(q + 7, out->sec))
        return lm_fail(LM_E_FORMAT, "%s/%s is not a key pair (\"public KEY\", \"secret KEY\")", dir,
                       file);
    return LM_OK;
}

lm_status lm_keys_load_public(const char *dir, const char *name, char pub[LM_KEY_Z85 + 1])
{
    char buf[256], file[64];
    snprintf(file, sizeof file, "%s.pub", name);
    lm_status st = read_small(dir, file, buf, sizeof buf);
    if (st == LM_OK && !take_key(buf + strspn(buf, " \t\r\n"), pub))
        st = lm_fail(LM_E_FORMAT, "%s/%s is not a public key", dir, file);
    return st;
}

lm_status lm_keys_load_allow(const char *dir, lm_allow *out)
{
    memset(out, 0, sizeof *out);
    char buf[65536];
    lm_status st = read_small(dir, "workers.allow", buf, sizeof buf);
    for (char *line = strtok(buf, "\n"); st == LM_OK && line; line = strtok(NULL, "\n")) {
        line += strspn(line, " \t\r");
        if (!*line || *line == '#')
            continue;
        char z[LM_KEY_Z85 + 1];
        uint8_t(*k)[32] = realloc(out->keys, (out->n + 1) * sizeof *k);
        if (!k)
            st = lm_fail(LM_E_NOMEM, "out of memory for the allow-list");
        else if (!take_key(line, z))
            st = lm_fail(LM_E_FORMAT, "%s/workers.allow: '%.40s' is not a public key", dir, line);
        else
            zmq_z85_decode(k[out->n++], z);
        if (k)
            out->keys = k;
    }
    if (st != LM_OK)
        lm_allow_free(out);
    return st;
}

void lm_allow_free(lm_allow *a)
{
    free(a->keys);
    memset(a, 0, sizeof *a);
}

int lm_allow_has(const lm_allow *a, const uint8_t key[32])
{
    for (uint32_t i = 0; i < a->n; i++)
        if (!memcmp(a->keys[i], key, 32))
            return 1;
    return 0;
}

static lm_status set_key(void *sock, int opt, const char *z85)
{
    if (zmq_setsockopt(sock, opt, z85, LM_KEY_Z85) != 0)
        return lm_fail(LM_E_INTERNAL, "setting a CURVE key: %s", zmq_strerror(zmq_errno()));
    return LM_OK;
}

lm_status lm_keys_client(void *sock, const char *dir)
{
    lm_keypair me;
    char server[LM_KEY_Z85 + 1];
    lm_status st = lm_keys_load_pair(dir, "worker", &me);
    if (st == LM_OK)
        st = lm_keys_load_public(dir, "coordinator", server);
    if (st == LM_OK)
        st = set_key(sock, ZMQ_CURVE_SERVERKEY, server);
    if (st == LM_OK)
        st = set_key(sock, ZMQ_CURVE_PUBLICKEY, me.pub);
    if (st == LM_OK)
        st = set_key(sock, ZMQ_CURVE_SECRETKEY, me.sec);
    return st;
}

lm_status lm_keys_server(void *sock, const char *dir)
{
    lm_keypair me;
    int one = 1;
    lm_status st = lm_keys_load_pair(dir, "coordinator", &me);
    if (st == LM_OK && zmq_setsockopt(sock, ZMQ_CURVE_SERVER, &one, sizeof one) != 0)
        st = lm_fail(LM_E_INTERNAL, "CURVE server: %s", zmq_strerror(zmq_errno()));
    if (st == LM_OK)
        st = set_key(sock, ZMQ_CURVE_SECRETKEY, me.sec);
    if (st == LM_OK && zmq_setsockopt(sock, ZMQ_ZAP_DOMAIN, "lumesh", 6) != 0)
        st = lm_fail(LM_E_INTERNAL, "ZAP domain: %s", zmq_strerror(zmq_errno()));
    return st;
}
