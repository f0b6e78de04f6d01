/* SPDX-License-Identifier: MIT */
/*
 * psc_io_load.h - load Periscope's sectioned files by path, the way the
 * device does: the whole file into 64-byte aligned memory, then core's own
 * parser, which points into it (nothing is copied). Errors name the file,
 * the problem and its byte offset:
 *   "scene.pano: CRC-32 mismatch: the file is corrupt (offset 20): checksum mismatch (corrupt data)"
 *
 * A new format adds a loader here: a struct of {buf, len, parsed}, a load
 * and a free of a few lines each around psc_io_container_load.
 */
#ifndef PSC_IO_LOAD_H
#define PSC_IO_LOAD_H

#include <stdbool.h>
#include <stddef.h>

#include "base/psc_container.h"
#include "fisheye/psc_fisheye.h"
#include "mesh/psc_mesh.h"
#include "pack/psc_pack.h"
#include "patch/psc_patch.h"
#include "shadow/psc_shadow.h"
#include "proxy/psc_proxy.h"

/** A scene pack loaded from disk: the aligned file bytes and the parsed view of them. */
typedef struct {
    void *buf;       /* 64-byte aligned, malloc'd */
    size_t len;
    psc_pack_t pack;
} psc_io_pack_t;

/** A mesh pack loaded from disk. */
typedef struct {
    void *buf;
    size_t len;
    psc_mesh_t mesh;
} psc_io_mesh_t;

/** A dual-fisheye table loaded from disk. */
typedef struct {
    void *buf;
    size_t len;
    psc_fisheye_t table;
} psc_io_fisheye_t;

int psc_io_pack_load(const char *path, psc_io_pack_t *pf, char *err, size_t errlen);
void psc_io_pack_free(psc_io_pack_t *pf);

int psc_io_mesh_load(const char *path, psc_io_mesh_t *mf, char *err, size_t errlen);
void psc_io_mesh_free(psc_io_mesh_t *mf);
/** Parse a mesh pack already in memory (aligned to 8), with the same messages (name: for them). */
int psc_io_mesh_parse_named(const char *name, const void *buf, size_t len, psc_mesh_t *mesh, char *err,
                            size_t errlen);

/** A patch pack loaded from disk. */
typedef struct {
    void *buf;
    size_t len;
    psc_patch_model_t model;
} psc_io_patch_t;

int psc_io_patch_load(const char *path, psc_io_patch_t *pf, char *err, size_t errlen);
void psc_io_patch_free(psc_io_patch_t *pf);
/** Parse a patch pack already in memory (aligned to 8), with the same messages (name: for them). */
int psc_io_patch_parse_named(const char *name, const void *buf, size_t len, psc_patch_model_t *model, char *err,
                             size_t errlen);

/** A shadow pack loaded from disk. */
typedef struct {
    void *buf;
    size_t len;
    psc_shadow_model_t model;
} psc_io_shadow_t;

int psc_io_shadow_load(const char *path, psc_io_shadow_t *sf, char *err, size_t errlen);
void psc_io_shadow_free(psc_io_shadow_t *sf);

/** A proxy pack loaded from disk. */
typedef struct {
    void *buf;
    size_t len;
    psc_proxy_model_t model;
} psc_io_proxy_t;

int psc_io_proxy_load(const char *path, psc_io_proxy_t *pf, char *err, size_t errlen);
void psc_io_proxy_free(psc_io_proxy_t *pf);

int psc_io_fisheye_load(const char *path, psc_io_fisheye_t *ff, char *err, size_t errlen);
void psc_io_fisheye_free(psc_io_fisheye_t *ff);

/**
 * "name: <prefix><what> (offset N): <status>" for a parse that failed with s
 * and e (prefix may be ""); returns -1.
 */
int psc_io_container_errorf(char *err, size_t errlen, const char *name, const char *prefix, psc_status_t s,
                            const psc_container_error_t *e);

/**
 * The common part of every loader: path must be a regular file (at most
 * 4 GiB, the container's limit) whose header is one of format fmt with the
 * file's own size (psc_container_check_head: checked on its first 32 bytes,
 * before the file is read; a problem is reported after prefix); then it is read whole into *buf and *len. 0, or
 * -1 with err naming the file and the problem.
 */
int psc_io_container_read(const char *path, const psc_container_format_t *fmt, const char *prefix, void **buf,
                          size_t *len, char *err, size_t errlen);

#endif
