/* SPDX-License-Identifier: MIT */
/* assimp.c - articulated and skinned models read through libassimp (gltf_model.h: glTF, glb and the other
 * formats it reads; OBJ is read by obj.c); gltf_model.c poses them. */
#include "import/gltf_model.h"
#include "psc_io_error.h"
#include "util/note_text.h"

#include <assimp/cimport.h>
#include <assimp/GltfMaterial.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* The Open Asset Import Library's matrix (row-major 4x4) as ours. */
static void from_ai(const struct aiMatrix4x4 *a, double m[12])
{
    const double v[12] = {a->a1, a->a2, a->a3, a->a4, a->b1, a->b2, a->b3, a->b4, a->c1, a->c2, a->c3, a->c4};
    memcpy(m, v, sizeof v);
}

/* ---- loading ----------------------------------------------------------------------------------------------- */

typedef struct {
    psc_gltf_t *g;
    const struct aiNode **node;   /* by joint */
    unsigned turned;              /* closed meshes found inside out */
} build_t;

static int add_joints(build_t *b, const struct aiNode *n, int32_t parent)
{
    psc_gltf_t *g = b->g;
    if (g->joint_count >= PSC_GLTF_MAX_JOINTS)
        return -1;
    if (n->mName.length >= sizeof g->joints[0].name)
        return -2;
    uint32_t j = g->joint_count++;
    psc_gltf_joint_t *jt = &g->joints[j];
    struct aiVector3D s, t;
    struct aiQuaternion q;
    aiDecomposeMatrix(&n->mTransformation, &s, &q, &t);
    *jt = (psc_gltf_joint_t){.parent = parent,
                             .rest = {{t.x, t.y, t.z}, {q.x, q.y, q.z, q.w}, {s.x, s.y, s.z}}};
    memcpy(jt->name, n->mName.data, n->mName.length);
    jt->name[n->mName.length] = '\0';
    b->node[j] = n;
    for (unsigned c = 0; c < n->mNumChildren; c++) {
        int rc = add_joints(b, n->mChildren[c], (int32_t)j);
        if (rc != 0)
            return rc;
    }
    return 0;
}

static uint32_t material_color(const struct aiScene *sc, unsigned mi)
{
    struct aiColor4D c = {0.8f, 0.8f, 0.8f, 1.0f};
    if (mi < sc->mNumMaterials &&
        aiGetMaterialColor(sc->mMaterials[mi], AI_MATKEY_BASE_COLOR, &c) != AI_SUCCESS &&
        aiGetMaterialColor(sc->mMaterials[mi], AI_MATKEY_COLOR_DIFFUSE, &c) != AI_SUCCESS)
        c = (struct aiColor4D){0.8f, 0.8f, 0.8f, 1.0f};
    double v[3] = {c.r, c.g, c.b};
    uint32_t out = 0;
    for (unsigned k = 0; k < 3; k++)
        out = (out << 8) | (uint32_t)lround(fmin(fmax(v[k], 0.0), 1.0) * 255.0);
    return out;
}

/* Keep the PSC_GLTF_WEIGHTS heaviest (joint, weight) of a vertex, sorted, normalised. */
static void add_weight(uint16_t *joint, double *weight, uint32_t j, double w)
{
    if (w <= weight[PSC_GLTF_WEIGHTS - 1u])
        return;
    unsigned at = PSC_GLTF_WEIGHTS - 1u;
    while (at > 0 && weight[at - 1u] < w) {
        weight[at] = weight[at - 1u];
        joint[at] = joint[at - 1u];
        at--;
    }
    weight[at] = w;
    joint[at] = (uint16_t)j;
}

/* Point p and normal n of vertex i of mesh am (hung from joint j) in model space, as at rest: through its node, or
 * through each bone's bind (offset) and node, weighed; the normal not normalised. */
static void to_model(const psc_gltf_t *g, const struct aiMesh *am, uint32_t j, const double (*rest_world)[12],
                     uint32_t i, const double p[3], const double n[3], double acc[3], double nacc[3])
{
    for (unsigned k = 0; k < 3; k++)
        acc[k] = nacc[k] = 0;
    if (am->mNumBones == 0) {
        psc_gltf_mat_point(rest_world[j], p, acc);
        psc_gltf_mat_dir(rest_world[j], n, nacc);
        return;
    }
    double total = 0;
    for (unsigned bi = 0; bi < am->mNumBones; bi++) {
        const struct aiBone *bone = am->mBones[bi];
        double wsum = 0;
        for (unsigned w2 = 0; w2 < bone->mNumWeights; w2++)
            if (bone->mWeights[w2].mVertexId == i)
                wsum += bone->mWeights[w2].mWeight;
        if (wsum <= 0)
            continue;
        total += wsum;
        double off[12], bind[12], q[3], qn[3];
        from_ai(&bone->mOffsetMatrix, off);
        psc_gltf_mat_mul(rest_world[psc_gltf_joint_named(g, bone->mName.data)], off, bind);
        psc_gltf_mat_point(bind, p, q);
        psc_gltf_mat_dir(bind, n, qn);
        for (unsigned k = 0; k < 3; k++) {
            acc[k] += wsum * q[k];
            nacc[k] += wsum * qn[k];
        }
    }
    for (unsigned k = 0; k < 3 && total > 0; k++) {
        acc[k] /= total;
        nacc[k] /= total;
    }
}

/* Mesh am's blend shapes (libassimp gives each target's positions and normals whole, not as deltas): their deltas
 * in model space, the mesh's weights. */
static int add_targets(psc_gltf_t *g, const struct aiMesh *am, uint32_t j, const double (*rest_world)[12],
                       uint32_t v0, const char *path, char *err, size_t errlen)
{
    uint32_t nt = 0, nv = am->mNumVertices;
    for (unsigned k = 0; k < am->mNumAnimMeshes; k++)
        nt += am->mAnimMeshes[k] && am->mAnimMeshes[k]->mVertices && am->mAnimMeshes[k]->mNumVertices == nv;
    if (nt == 0)
        return 0;
    if (g->target_count + nt > PSC_GLTF_MAX_TARGETS)
        return psc_io_errorf(err, errlen, path, "mesh '%s': more than %u morph targets", am->mName.data,
                             PSC_GLTF_MAX_TARGETS);
    void *grown = realloc(g->morphs, (g->morph_count + 1u) * sizeof *g->morphs);
    if (!grown)
        return psc_io_errorf(err, errlen, path, "out of memory");
    g->morphs = grown;
    psc_gltf_morph_t *mo = &g->morphs[g->morph_count++];
    memset(mo, 0, sizeof *mo);
    mo->v0 = v0;
    mo->nv = nv;
    mo->target_count = nt;
    mo->joint = (int32_t)j;
    mo->dpos = calloc((size_t)nt * nv * 3u, sizeof *mo->dpos);
    mo->dnrm = am->mNormals ? calloc((size_t)nt * nv * 3u, sizeof *mo->dnrm) : NULL;
    mo->weight = calloc(nt, sizeof *mo->weight);
    void *names = realloc(g->target_name, ((size_t)g->target_count + nt) * sizeof *g->target_name);
    if (names)
        g->target_name = names;
    if (!mo->dpos || (am->mNormals && !mo->dnrm) || !mo->weight || !names)
        return psc_io_errorf(err, errlen, path, "out of memory");
    uint32_t t = 0;
    for (unsigned k = 0; k < am->mNumAnimMeshes; k++) {
        const struct aiAnimMesh *a = am->mAnimMeshes[k];
        if (!a || !a->mVertices || a->mNumVertices != nv)
            continue;
        mo->weight[t] = a->mWeight;
        snprintf(g->target_name[g->target_count + t], sizeof g->target_name[0], "%.*s",
                 (int)(a->mName.length < sizeof g->target_name[0] ? a->mName.length : sizeof g->target_name[0] - 1),
                 a->mName.data);
        for (uint32_t i = 0; i < nv; i++) {
            double p[3] = {am->mVertices[i].x, am->mVertices[i].y, am->mVertices[i].z};
            double q[3] = {a->mVertices[i].x, a->mVertices[i].y, a->mVertices[i].z}, n[3] = {0, 0, 1}, tn[3];
            if (am->mNormals)
                n[0] = am->mNormals[i].x, n[1] = am->mNormals[i].y, n[2] = am->mNormals[i].z;
            memcpy(tn, n, sizeof tn);
            if (am->mNormals && a->mNormals)
                tn[0] = a->mNormals[i].x, tn[1] = a->mNormals[i].y, tn[2] = a->mNormals[i].z;
            double bp[3], bn[3], tp[3], tnm[3];
            to_model(g, am, j, rest_world, i, p, n, bp, bn);
            to_model(g, am, j, rest_world, i, q, tn, tp, tnm);
            double l = sqrt(bn[0] * bn[0] + bn[1] * bn[1] + bn[2] * bn[2]);
            for (unsigned c = 0; c < 3; c++) {
                mo->dpos[((size_t)t * nv + i) * 3u + c] = tp[c] - bp[c];
                if (mo->dnrm) /* against the unit base normal the model keeps */
                    mo->dnrm[((size_t)t * nv + i) * 3u + c] = l > 0 ? (tnm[c] - bn[c]) / l : 0;
            }
        }
        t++;
    }
    g->target_count += nt;
    return 0;
}

/* A material's opacity, 0..256: a glTF material's base-colour alpha when its alphaMode is BLEND (OPAQUE and MASK
 * draw opaque), another format's opacity (an OBJ's d or 1 - Tr, read by libassimp). */
static uint16_t material_opacity(const struct aiScene *sc, unsigned mi)
{
    if (mi >= sc->mNumMaterials)
        return 256;
    const struct aiMaterial *mat = sc->mMaterials[mi];
    struct aiString mode;
    float o = 1.0f;
    if (aiGetMaterialString(mat, AI_MATKEY_GLTF_ALPHAMODE, &mode) == AI_SUCCESS) {
        struct aiColor4D c = {1, 1, 1, 1};
        if (strcmp(mode.data, "BLEND") != 0)
            return 256;
        if (aiGetMaterialColor(mat, AI_MATKEY_BASE_COLOR, &c) == AI_SUCCESS)
            o = c.a;
        else if (aiGetMaterialFloat(mat, AI_MATKEY_OPACITY, &o) != AI_SUCCESS)
            o = 1.0f;
    } else if (aiGetMaterialFloat(mat, AI_MATKEY_OPACITY, &o) != AI_SUCCESS) {
        o = 1.0f;
    }
    return (uint16_t)lround(fmin(fmax(o, 0.0), 1.0) * 256.0);
}

/* Append the vertices and triangles of mesh mi hung from joint j. */
static int add_mesh(build_t *b, const struct aiScene *sc, unsigned mi, uint32_t j, const double (*rest_world)[12],
                    const char *path, char *err, size_t errlen)
{
    psc_gltf_t *g = b->g;
    psc_model_t *m = &g->mesh;
    const struct aiMesh *am = sc->mMeshes[mi];
    uint32_t v0 = m->vertex_count, nv = am->mNumVertices, nt = 0;
    for (unsigned f = 0; f < am->mNumFaces; f++)
        nt += am->mFaces[f].mNumIndices == 3;
    if ((uint64_t)v0 + nv > PSC_GLTF_MAX_VERTICES)
        return psc_io_errorf(err, errlen, path, "more than %u vertices", PSC_GLTF_MAX_VERTICES);
    void *p0 = realloc(m->pos, (v0 + nv) * 3 * sizeof *m->pos), *p1 = p0 ? realloc(m->normal, (v0 + nv) * 3 * sizeof *m->normal) : NULL;
    if (p0)
        m->pos = p0;
    if (p1)
        m->normal = p1;
    void *p2 = p1 ? realloc(m->color, (v0 + nv) * sizeof *m->color) : NULL;
    if (p2)
        m->color = p2;
    void *p3 = p2 ? realloc(g->joint, (v0 + nv) * sizeof *g->joint) : NULL;
    if (p3)
        g->joint = p3;
    void *p4 = p3 ? realloc(g->weight, (v0 + nv) * sizeof *g->weight) : NULL;
    if (p4)
        g->weight = p4;
    void *p5 = p4 ? realloc(m->index, ((size_t)m->triangle_count + nt) * 3 * sizeof *m->index) : NULL;
    if (p5)
        m->index = p5;
    void *p6 = p5 ? realloc(g->tri_opacity_q8, ((size_t)m->triangle_count + nt) * sizeof *g->tri_opacity_q8) : NULL;
    if (p6)
        g->tri_opacity_q8 = p6;
    if (!p6)
        return psc_io_errorf(err, errlen, path, "out of memory");
    uint16_t opacity = material_opacity(sc, am->mMaterialIndex);
    uint32_t col = material_color(sc, am->mMaterialIndex);
    for (uint32_t i = 0; i < nv; i++) {
        memset(g->joint[v0 + i], 0, sizeof g->joint[0]);
        memset(g->weight[v0 + i], 0, sizeof g->weight[0]);
        m->color[v0 + i] = col;
    }
    for (unsigned bi = 0; bi < am->mNumBones; bi++) {
        const struct aiBone *bone = am->mBones[bi];
        int32_t bj = psc_gltf_joint_named(g, bone->mName.data);
        if (bj < 0)
            return psc_io_errorf(err, errlen, path, "mesh '%s': bone '%s' names no node", am->mName.data,
                                 bone->mName.data);
        for (unsigned w = 0; w < bone->mNumWeights; w++)
            if (bone->mWeights[w].mVertexId < nv)
                add_weight(g->joint[v0 + bone->mWeights[w].mVertexId], g->weight[v0 + bone->mWeights[w].mVertexId],
                           (uint32_t)bj, bone->mWeights[w].mWeight);
    }
    for (uint32_t i = 0; i < nv; i++) {
        double *w = g->weight[v0 + i], sum = 0;
        for (unsigned k = 0; k < PSC_GLTF_WEIGHTS; k++)
            sum += w[k];
        if (am->mNumBones == 0 || sum <= 0) {   /* rigid: on the node it hangs from */
            g->joint[v0 + i][0] = (uint16_t)j;
            w[0] = 1.0;
            sum = 1.0;
        }
        for (unsigned k = 0; k < PSC_GLTF_WEIGHTS; k++)
            w[k] /= sum;
        if (w[1] > 0)
            g->skinned = true;
        /* the vertex at rest in model space: through its node, or through each bone's bind (offset) and node */
        double p[3] = {am->mVertices[i].x, am->mVertices[i].y, am->mVertices[i].z}, n[3] = {0, 0, 1};
        if (am->mNormals)
            n[0] = am->mNormals[i].x, n[1] = am->mNormals[i].y, n[2] = am->mNormals[i].z;
        double acc[3], nacc[3];
        to_model(g, am, j, rest_world, i, p, n, acc, nacc);
        double l = sqrt(nacc[0] * nacc[0] + nacc[1] * nacc[1] + nacc[2] * nacc[2]);
        for (unsigned k = 0; k < 3; k++) {
            m->pos[3 * (v0 + i) + k] = acc[k];
            m->normal[3 * (v0 + i) + k] = l > 0 ? nacc[k] / l : (k == 2);
        }
    }
    if (add_targets(g, am, j, rest_world, v0, path, err, errlen) != 0)
        return -1;
    uint32_t t0 = m->triangle_count;
    for (unsigned f = 0; f < am->mNumFaces; f++) {
        if (am->mFaces[f].mNumIndices != 3)
            continue;   /* points and lines */
        for (unsigned k = 0; k < 3; k++) {
            unsigned vi = am->mFaces[f].mIndices[k];
            if (vi >= nv)
                return psc_io_errorf(err, errlen, path, "mesh '%s': a face names vertex %u of %u", am->mName.data,
                                     vi, nv);
            m->index[3 * m->triangle_count + k] = v0 + vi;
        }
        g->tri_opacity_q8[m->triangle_count] = opacity;
        m->triangle_count++;
    }
    m->vertex_count += nv;
    if (psc_gltf_turn_outward(m, v0, v0 + nv, t0, m->triangle_count))
        b->turned++;
    return 0;
}

static int add_channels(psc_gltf_t *g, const struct aiScene *sc, const char *path, char *err, size_t errlen)
{
    if (sc->mNumAnimations == 0)
        return 0;
    const struct aiAnimation *a = sc->mAnimations[0];
    double tps = a->mTicksPerSecond > 0 ? a->mTicksPerSecond : 25.0;
    g->duration = a->mDuration / tps;
    g->channels = calloc(a->mNumChannels ? a->mNumChannels : 1, sizeof *g->channels);
    if (!g->channels)
        return psc_io_errorf(err, errlen, path, "out of memory");
    for (unsigned c = 0; c < a->mNumChannels; c++) {
        const struct aiNodeAnim *na = a->mChannels[c];
        int32_t j = psc_gltf_joint_named(g, na->mNodeName.data);
        if (j < 0)
            continue;   /* animates a node that is not there: nothing to move */
        psc_gltf_channel_t *ch = &g->channels[g->channel_count++];
        ch->joint = (uint32_t)j;
        ch->nt = na->mNumPositionKeys;
        ch->nr = na->mNumRotationKeys;
        ch->ns = na->mNumScalingKeys;
        ch->t = calloc(ch->nt + 1u, sizeof *ch->t);
        ch->r = calloc(ch->nr + 1u, sizeof *ch->r);
        ch->s = calloc(ch->ns + 1u, sizeof *ch->s);
        if (!ch->t || !ch->r || !ch->s)
            return psc_io_errorf(err, errlen, path, "out of memory");
        for (unsigned k = 0; k < ch->nt; k++)
            ch->t[k] = (psc_gltf_key_t){na->mPositionKeys[k].mTime / tps,
                                        {na->mPositionKeys[k].mValue.x, na->mPositionKeys[k].mValue.y,
                                         na->mPositionKeys[k].mValue.z, 0}};
        for (unsigned k = 0; k < ch->nr; k++)
            ch->r[k] = (psc_gltf_key_t){na->mRotationKeys[k].mTime / tps,
                                        {na->mRotationKeys[k].mValue.x, na->mRotationKeys[k].mValue.y,
                                         na->mRotationKeys[k].mValue.z, na->mRotationKeys[k].mValue.w}};
        for (unsigned k = 0; k < ch->ns; k++)
            ch->s[k] = (psc_gltf_key_t){na->mScalingKeys[k].mTime / tps,
                                        {na->mScalingKeys[k].mValue.x, na->mScalingKeys[k].mValue.y,
                                         na->mScalingKeys[k].mValue.z, 0}};
    }
    return 0;
}

/* The first animation's weights channels (by the node a mesh hangs from): each morph's keys, the weights its keys
 * do not name its own. */
static int add_weight_channels(psc_gltf_t *g, const struct aiScene *sc, const char *path, char *err, size_t errlen)
{
    if (sc->mNumAnimations == 0 || g->morph_count == 0)
        return 0;
    const struct aiAnimation *a = sc->mAnimations[0];
    double tps = a->mTicksPerSecond > 0 ? a->mTicksPerSecond : 25.0;
    for (unsigned c = 0; c < a->mNumMorphMeshChannels; c++) {
        const struct aiMeshMorphAnim *ch = a->mMorphMeshChannels[c];
        if (!ch || ch->mNumKeys == 0)
            continue;
        int32_t j = psc_gltf_joint_named(g, ch->mName.data);
        for (uint32_t k = 0; k < g->morph_count; k++) {
            psc_gltf_morph_t *mo = &g->morphs[k];
            if (mo->joint != j || mo->key_count)
                continue;
            mo->key_time = calloc(ch->mNumKeys, sizeof *mo->key_time);
            mo->key_weight = calloc((size_t)ch->mNumKeys * mo->target_count, sizeof *mo->key_weight);
            if (!mo->key_time || !mo->key_weight)
                return psc_io_errorf(err, errlen, path, "out of memory");
            for (unsigned kk = 0; kk < ch->mNumKeys; kk++) {
                const struct aiMeshMorphKey *key = &ch->mKeys[kk];
                double *w = &mo->key_weight[(size_t)kk * mo->target_count];
                memcpy(w, mo->weight, mo->target_count * sizeof *w);
                for (unsigned v = 0; v < key->mNumValuesAndWeights; v++)
                    if (key->mValues[v] < mo->target_count)
                        w[key->mValues[v]] = key->mWeights[v];
                mo->key_time[kk] = key->mTime / tps;
                if (kk > 0 && mo->key_time[kk] < mo->key_time[kk - 1u])
                    return psc_io_errorf(err, errlen, path, "a weights channel's keys go back in time");
            }
            mo->key_count = ch->mNumKeys;
            if (g->duration < mo->key_time[ch->mNumKeys - 1u])
                g->duration = mo->key_time[ch->mNumKeys - 1u];
        }
    }
    return 0;
}

int psc_assimp_load(const char *path, psc_gltf_t *out, char *note, size_t notelen, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    const struct aiScene *sc = aiImportFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                      aiProcess_GenSmoothNormals | aiProcess_LimitBoneWeights |
                                                      aiProcess_SortByPType);
    if (sc == NULL)
        return psc_io_errorf(err, errlen, path, "cannot be read as a model: %s", aiGetErrorString());
    int rc = -1;
    build_t b = {out, calloc(PSC_GLTF_MAX_JOINTS, sizeof *b.node), 0};
    double (*rest_world)[12] = NULL;
    psc_gltf_trs_t *rest = NULL;
    out->joints = calloc(PSC_GLTF_MAX_JOINTS, sizeof *out->joints);
    if (!b.node || !out->joints) {
        psc_io_errorf(err, errlen, path, "out of memory");
        goto done;
    }
    int jr = sc->mRootNode ? add_joints(&b, sc->mRootNode, -1) : -1;
    if (jr != 0) {
        psc_io_errorf(err, errlen, path, jr == -2 ? "a node's name is longer than %zu bytes"
                                                  : "no node hierarchy, or more than %zu nodes",
                      jr == -2 ? sizeof out->joints[0].name - 1u : (size_t)PSC_GLTF_MAX_JOINTS);
        goto done;
    }
    rest_world = malloc(out->joint_count * sizeof *rest_world);
    rest = malloc(out->joint_count * sizeof *rest);
    if (!rest_world || !rest) {
        psc_io_errorf(err, errlen, path, "out of memory");
        goto done;
    }
    for (uint32_t j = 0; j < out->joint_count; j++)
        rest[j] = out->joints[j].rest;
    psc_gltf_worlds(out, rest, NULL, rest_world);
    for (uint32_t j = 0; j < out->joint_count; j++)
        for (unsigned k = 0; k < b.node[j]->mNumMeshes; k++)
            if (b.node[j]->mMeshes[k] < sc->mNumMeshes &&
                add_mesh(&b, sc, b.node[j]->mMeshes[k], j, (const double(*)[12])rest_world, path, err, errlen) != 0)
                goto done;
    if (out->mesh.triangle_count == 0) {
        psc_io_errorf(err, errlen, path, "no triangles");
        goto done;
    }
    if (add_channels(out, sc, path, err, errlen) != 0 || add_weight_channels(out, sc, path, err, errlen) != 0)
        goto done;
    psc_note_add(note, notelen, "%u vertices, %u triangles, %u nodes, %s, %s", out->mesh.vertex_count,
                 out->mesh.triangle_count, out->joint_count, out->skinned ? "skinned" : "rigid parts",
                 out->channel_count || out->duration > 0 ? "animated" : "no animation");
    if (out->target_count)
        psc_note_add(note, notelen, "%u morph targets in %u mesh%s", out->target_count, out->morph_count,
                     out->morph_count > 1 ? "es" : "");
    if (b.turned)
        psc_note_add(note, notelen, "%u closed mesh%s faced inwards: turned outward", b.turned, b.turned > 1 ? "es" : "");
    rc = 0;
done:
    free(b.node);
    free(rest_world);
    free(rest);
    aiReleaseImport(sc);
    if (rc != 0)
        psc_gltf_free(out);
    return rc;
}
