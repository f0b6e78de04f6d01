/* SPDX-License-Identifier: MIT */
/*
 * psc_io_load.c - load scene packs, mesh packs and fisheye tables by path and
 * parse them with core's parsers (exactly what the device does).
 */
#include "psc_io_load.h"
#include "psc_io_error.h"
#include "psc_io_file.h"

#include <stdint.h>
#include <unistd.h>
#include <stdlib.h>
#include <string.h>

int psc_io_container_errorf(char *err, size_t errlen, const char *name, const char *prefix, psc_status_t s,
                            const psc_container_error_t *e)
{
    return psc_io_errorf(err, errlen, name, "%s%s (offset %u): %s", prefix, e->what ? e->what : "invalid file",
                         (unsigned)e->offset, psc_status_str(s));
}

int psc_io_container_read(const char *path, const psc_container_format_t *fmt, const char *prefix, void **buf,
                          size_t *len, char *err, size_t errlen)
{
    uint8_t head[PSC_CONTAINER_HEADER_SIZE];
    psc_container_error_t e = {0};
    uint64_t size;
    psc_status_t s;
    int fd;

    *buf = NULL;
    *len = 0;
    if (!path)
        return psc_io_errorf(err, errlen, "(file)", "no file to load");
    /* the container records its size in 32 bits */
    if (psc_io_open_regular(path, UINT32_MAX, &fd, &size, err, errlen) != 0)
        return -1;
    /* the header first: a file of another kind or size is refused before it is read whole */
    size_t head_len = size < sizeof head ? (size_t)size : sizeof head;
    int rc = psc_io_read_at(fd, path, head, head_len, 0, err, errlen);
    if (rc == 0 && (s = psc_container_check_head(head, head_len, size, fmt, &e)) != PSC_OK)
        rc = psc_io_container_errorf(err, errlen, path, prefix, s, &e);
    if (rc == 0)
        rc = psc_io_read_fd_aligned(fd, path, size, buf, len, err, errlen);
    close(fd);
    return rc;
}

int psc_io_pack_load(const char *path, psc_io_pack_t *pf, char *err, size_t errlen)
{
    psc_container_error_t e = {0};
    psc_status_t s;

    memset(pf, 0, sizeof *pf);
    if (psc_io_container_read(path, &psc_pack_format, "", &pf->buf, &pf->len, err, errlen) != 0)
        return -1;
    if ((s = psc_pack_parse(pf->buf, pf->len, &pf->pack, &e)) != PSC_OK) {
        psc_io_pack_free(pf);
        return psc_io_container_errorf(err, errlen, path, "", s, &e);
    }
    return 0;
}

void psc_io_pack_free(psc_io_pack_t *pf)
{
    if (!pf)
        return;
    free(pf->buf);
    memset(pf, 0, sizeof *pf);
}

int psc_io_mesh_parse_named(const char *name, const void *buf, size_t len, psc_mesh_t *mesh, char *err,
                            size_t errlen)
{
    psc_container_error_t e = {0};
    psc_status_t s = psc_mesh_parse(buf, len, mesh, &e);

    return s == PSC_OK ? 0 : psc_io_container_errorf(err, errlen, name, "", s, &e);
}

int psc_io_mesh_load(const char *path, psc_io_mesh_t *mf, char *err, size_t errlen)
{
    memset(mf, 0, sizeof *mf);
    if (psc_io_container_read(path, &psc_mesh_format, "", &mf->buf, &mf->len, err, errlen) != 0)
        return -1;
    if (psc_io_mesh_parse_named(path, mf->buf, mf->len, &mf->mesh, err, errlen) != 0) {
        psc_io_mesh_free(mf);
        return -1;
    }
    return 0;
}

void psc_io_mesh_free(psc_io_mesh_t *mf)
{
    if (!mf)
        return;
    free(mf->buf);
    memset(mf, 0, sizeof *mf);
}

int psc_io_patch_parse_named(const char *name, const void *buf, size_t len, psc_patch_model_t *model, char *err,
                             size_t errlen)
{
    psc_container_error_t e = {0};
    psc_status_t s = psc_patch_parse(buf, len, model, &e);

    return s == PSC_OK ? 0 : psc_io_container_errorf(err, errlen, name, "not a usable patch pack: ", s, &e);
}

int psc_io_patch_load(const char *path, psc_io_patch_t *pf, char *err, size_t errlen)
{
    memset(pf, 0, sizeof *pf);
    if (psc_io_container_read(path, &psc_patch_format, "not a usable patch pack: ",
                              &pf->buf, &pf->len, err, errlen) != 0)
        return -1;
    if (psc_io_patch_parse_named(path, pf->buf, pf->len, &pf->model, err, errlen) != 0) {
        psc_io_patch_free(pf);
        return -1;
    }
    return 0;
}

void psc_io_patch_free(psc_io_patch_t *pf)
{
    if (!pf)
        return;
    free(pf->buf);
    memset(pf, 0, sizeof *pf);
}

int psc_io_shadow_load(const char *path, psc_io_shadow_t *sf, char *err, size_t errlen)
{
    psc_container_error_t e = {0};
    psc_status_t s;

    memset(sf, 0, sizeof *sf);
    if (psc_io_container_read(path, &psc_shadow_format, "not a usable shadow pack: ",
                              &sf->buf, &sf->len, err, errlen) != 0)
        return -1;
    if ((s = psc_shadow_parse(sf->buf, sf->len, &sf->model, &e)) != PSC_OK) {
        psc_io_shadow_free(sf);
        return psc_io_container_errorf(err, errlen, path, "not a usable shadow pack: ", s, &e);
    }
    return 0;
}

void psc_io_shadow_free(psc_io_shadow_t *sf)
{
    if (!sf)
        return;
    free(sf->buf);
    memset(sf, 0, sizeof *sf);
}

int psc_io_proxy_load(const char *path, psc_io_proxy_t *pf, char *err, size_t errlen)
{
    psc_container_error_t e = {0};
    psc_status_t s;

    memset(pf, 0, sizeof *pf);
    if (psc_io_container_read(path, &psc_proxy_format, "not a usable proxy pack: ",
                              &pf->buf, &pf->len, err, errlen) != 0)
        return -1;
    if ((s = psc_proxy_parse(pf->buf, pf->len, &pf->model, &e)) != PSC_OK) {
        psc_io_proxy_free(pf);
        return psc_io_container_errorf(err, errlen, path, "not a usable proxy pack: ", s, &e);
    }
    return 0;
}

void psc_io_proxy_free(psc_io_proxy_t *pf)
{
    if (!pf)
        return;
    free(pf->buf);
    memset(pf, 0, sizeof *pf);
}

int psc_io_fisheye_load(const char *path, psc_io_fisheye_t *ff, char *err, size_t errlen)
{
    psc_container_error_t e = {0};
    psc_status_t s;

    memset(ff, 0, sizeof *ff);
    if (psc_io_container_read(path, &psc_fisheye_format, "not a usable dual-fisheye table: ",
                              &ff->buf, &ff->len, err, errlen) != 0)
        return -1;
    if ((s = psc_fisheye_parse(ff->buf, ff->len, &ff->table, &e)) != PSC_OK) {
        psc_io_fisheye_free(ff);
        return psc_io_container_errorf(err, errlen, path, "not a usable dual-fisheye table: ", s, &e);
    }
    return 0;
}

void psc_io_fisheye_free(psc_io_fisheye_t *ff)
{
    if (!ff)
        return;
    free(ff->buf);
    memset(ff, 0, sizeof *ff);
}
