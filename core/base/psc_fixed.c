/* SPDX-License-Identifier: MIT */
/*
 * psc_fixed.c - integer square root, rounded division and CORDIC trigonometry.
 *
 * CORDIC runs on 64-bit integers with the operands normalised to about 2^61,
 * so the shift truncations are far below the result's last bit; 40 iterations
 * leave a residual angle far under one binary-angle unit. Right shifts of negative
 * values are arithmetic on every compiler Periscope supports (gcc, clang).
 */
#include "base/psc_fixed.h"

/* atan(2^-i) in binary angles with 16 extra fraction bits (2^48 per turn),
 * rounded: the extra bits keep 40 table roundings below one output unit. */
static const int64_t cordic_atan[40] = {
    INT64_C(35184372088832),
    INT64_C(20770547670515),
    INT64_C(10974586953444),
    INT64_C(5570871696862),
    INT64_C(2796246208089),
    INT64_C(1399486241028),
    INT64_C(699913886760),
    INT64_C(349978300884),
    INT64_C(174991820497),
    INT64_C(87496244017),
    INT64_C(43748163730),
    INT64_C(21874087080),
    INT64_C(10937044192),
    INT64_C(5468522177),
    INT64_C(2734261099),
    INT64_C(1367130551),
    INT64_C(683565276),
    INT64_C(341782638),
    INT64_C(170891319),
    INT64_C(85445659),
    INT64_C(42722830),
    INT64_C(21361415),
    INT64_C(10680707),
    INT64_C(5340354),
    INT64_C(2670177),
    INT64_C(1335088),
    INT64_C(667544),
    INT64_C(333772),
    INT64_C(166886),
    INT64_C(83443),
    INT64_C(41722),
    INT64_C(20861),
    INT64_C(10430),
    INT64_C(5215),
    INT64_C(2608),
    INT64_C(1304),
    INT64_C(652),
    INT64_C(326),
    INT64_C(163),
    INT64_C(81)
};

/* 1/K, K = prod sqrt(1 + 2^-2i), the CORDIC gain, Q2.61. */
#define CORDIC_KINV_Q61 INT64_C(1400229935014726656)

uint32_t psc_isqrt64(uint64_t v)
{
    /* Digit-by-digit: one result bit per step, from the top. */
    uint64_t rem = v, root = 0, bit = (uint64_t)1 << 62;
    while (bit > v)
        bit >>= 2;
    while (bit != 0) {
        if (rem >= root + bit) {
            rem -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    return (uint32_t)root;
}

int64_t psc_div_round64(int64_t n, int64_t d)
{
    /* Magnitudes in unsigned arithmetic so INT64_MIN cannot overflow. */
    uint64_t un = n < 0 ? (uint64_t)0 - (uint64_t)n : (uint64_t)n;
    uint64_t ud = d < 0 ? (uint64_t)0 - (uint64_t)d : (uint64_t)d;
    uint64_t q = un / ud, r = un % ud;
    if (r >= ud - r) /* r >= d/2 without overflow: ties away from zero */
        q++;
    if ((n < 0) != (d < 0))
        return q == 0 ? 0 : -(int64_t)(q - 1u) - 1; /* q may be 2^63: negate without overflow */
    return (int64_t)q;
}

void psc_sincos(psc_bam_t a, int32_t *sin_q30, int32_t *cos_q30)
{
    int64_t z = (int64_t)(int32_t)a * 65536; /* [-180, 180) degrees, 2^48 per turn */
    bool flip = false;
    if (z > (int64_t)PSC_BAM_90 * 65536) {
        z -= (int64_t)PSC_BAM_180 * 65536;
        flip = true;
    } else if (z < -(int64_t)PSC_BAM_90 * 65536) {
        z += (int64_t)PSC_BAM_180 * 65536;
        flip = true;
    }
    int64_t x = CORDIC_KINV_Q61, y = 0;
    for (unsigned i = 0; i < 40; i++) {
        int64_t dx = y >> i, dy = x >> i;
        if (z >= 0) {
            x -= dx;
            y += dy;
            z -= cordic_atan[i];
        } else {
            x += dx;
            y -= dy;
            z += cordic_atan[i];
        }
    }
    int32_t c = (int32_t)psc_shr_round64(x, 31), s = (int32_t)psc_shr_round64(y, 31);
    if (flip) {
        c = -c;
        s = -s;
    }
    if (sin_q30)
        *sin_q30 = s;
    if (cos_q30)
        *cos_q30 = c;
}

/* log2(1 + i/256) in Q0.8, rounded (255 at the top: log2(511/256) * 256 = 255.4). */
static const uint8_t log2_mantissa_q8[256] = {
    0, 1, 3, 4, 6, 7, 9, 10, 11, 13, 14, 16, 17, 18, 20, 21,
    22, 24, 25, 26, 28, 29, 30, 32, 33, 34, 36, 37, 38, 40, 41, 42,
    44, 45, 46, 47, 49, 50, 51, 52, 54, 55, 56, 57, 59, 60, 61, 62,
    63, 65, 66, 67, 68, 69, 71, 72, 73, 74, 75, 77, 78, 79, 80, 81,
    82, 84, 85, 86, 87, 88, 89, 90, 92, 93, 94, 95, 96, 97, 98, 99,
    100, 102, 103, 104, 105, 106, 107, 108, 109, 110, 111, 112, 113, 114, 116, 117,
    118, 119, 120, 121, 122, 123, 124, 125, 126, 127, 128, 129, 130, 131, 132, 133,
    134, 135, 136, 137, 138, 139, 140, 141, 142, 143, 144, 145, 146, 147, 148, 149,
    150, 151, 152, 153, 154, 155, 155, 156, 157, 158, 159, 160, 161, 162, 163, 164,
    165, 166, 167, 168, 169, 169, 170, 171, 172, 173, 174, 175, 176, 177, 178, 178,
    179, 180, 181, 182, 183, 184, 185, 185, 186, 187, 188, 189, 190, 191, 192, 192,
    193, 194, 195, 196, 197, 198, 198, 199, 200, 201, 202, 203, 203, 204, 205, 206,
    207, 208, 208, 209, 210, 211, 212, 212, 213, 214, 215, 216, 216, 217, 218, 219,
    220, 220, 221, 222, 223, 224, 224, 225, 226, 227, 228, 228, 229, 230, 231, 231,
    232, 233, 234, 234, 235, 236, 237, 238, 238, 239, 240, 241, 241, 242, 243, 244,
    244, 245, 246, 247, 247, 248, 249, 249, 250, 251, 252, 252, 253, 254, 255, 255,
};

static unsigned bit_length(uint64_t v)
{
#if defined(__GNUC__) || defined(__clang__)
    return v ? 64u - (unsigned)__builtin_clzll(v) : 0u; /* one instruction on most targets */
#else
    unsigned n = 0;
    while (v) {
        n++;
        v >>= 1;
    }
    return n;
#endif
}

psc_bam_t psc_atan2(int32_t y, int32_t x, uint32_t *mag)
{
    if (x == 0 && y == 0) {
        if (mag)
            *mag = 0;
        return 0;
    }
    int64_t X = x, Y = y;
    psc_bam_t base = 0;
    if (X < 0) { /* rotate by 180 degrees so CORDIC starts in its range */
        X = -X;
        Y = -Y;
        base = PSC_BAM_180;
    }
    uint64_t m = (uint64_t)(X > (Y < 0 ? -Y : Y) ? X : (Y < 0 ? -Y : Y));
    unsigned s = 61u - bit_length(m); /* m <= 2^31, so s >= 29 */
    X *= (int64_t)1 << s;
    Y *= (int64_t)1 << s;
    int64_t z = 0;
    for (unsigned i = 0; i < 40; i++) {
        int64_t dx = Y >> i, dy = X >> i;
        if (Y > 0) {
            X += dx;
            Y -= dy;
            z += cordic_atan[i];
        } else {
            X -= dx;
            Y += dy;
            z -= cordic_atan[i];
        }
    }
    if (mag) {
        /* Exact: x^2 + y^2 <= 2^63 fits, and the floor root is rounded up
         * when (r + 1/2)^2 <= v, i.e. r^2 + r < v. */
        uint64_t ax = x < 0 ? (uint64_t)0 - (uint64_t)(int64_t)x : (uint64_t)x;
        uint64_t ay = y < 0 ? (uint64_t)0 - (uint64_t)(int64_t)y : (uint64_t)y;
        uint64_t v = ax * ax + ay * ay;
        uint64_t r = psc_isqrt64(v);
        if (r * r + r < v)
            r++;
        *mag = r > UINT32_MAX ? UINT32_MAX : (uint32_t)r;
    }
    return base + (psc_bam_t)(uint32_t)psc_shr_round64(z, 16);
}

int32_t psc_log2_q8(uint64_t v)
{
    if (v == 0)
        return INT32_MIN;
    unsigned e = bit_length(v) - 1u; /* 2^e <= v < 2^(e+1) */
    uint32_t m = e >= 8u ? (uint32_t)(v >> (e - 8u)) & 255u : (uint32_t)(v << (8u - e)) & 255u;
    return (int32_t)(e * 256u + log2_mantissa_q8[m]);
}

/* 2^14 sqrt(512 / (i + 0.5)) for i = 128..511: 1/sqrt of the mantissa's top nine bits (at the middle of each
 * step), Q2.14 (`python3 -c "import math; print([round(math.sqrt(2**37 / (i + 0.5))) for i in range(128, 512)])"`). */
static const uint16_t rsqrt_mantissa_q14[384] = {
    32704, 32578, 32453, 32329, 32207, 32086, 31966, 31848, 31731, 31616, 31501, 31388,
    31276, 31166, 31056, 30948, 30840, 30734, 30629, 30525, 30422, 30320, 30219, 30120,
    30021, 29923, 29826, 29730, 29635, 29540, 29447, 29354, 29263, 29172, 29082, 28993,
    28905, 28817, 28731, 28645, 28560, 28475, 28392, 28309, 28227, 28145, 28064, 27984,
    27905, 27826, 27748, 27671, 27594, 27518, 27442, 27368, 27293, 27220, 27147, 27074,
    27002, 26931, 26860, 26790, 26720, 26651, 26582, 26514, 26447, 26380, 26313, 26247,
    26182, 26117, 26052, 25988, 25924, 25861, 25799, 25736, 25674, 25613, 25552, 25492,
    25432, 25372, 25313, 25254, 25196, 25138, 25080, 25023, 24966, 24910, 24854, 24798,
    24743, 24688, 24633, 24579, 24525, 24472, 24419, 24366, 24313, 24261, 24209, 24158,
    24107, 24056, 24005, 23955, 23905, 23856, 23807, 23758, 23709, 23661, 23613, 23565,
    23518, 23470, 23423, 23377, 23331, 23284, 23239, 23193, 23148, 23103, 23058, 23014,
    22969, 22926, 22882, 22838, 22795, 22752, 22709, 22667, 22625, 22583, 22541, 22499,
    22458, 22417, 22376, 22335, 22295, 22255, 22215, 22175, 22135, 22096, 22057, 22018,
    21979, 21941, 21902, 21864, 21826, 21789, 21751, 21714, 21677, 21640, 21603, 21566,
    21530, 21494, 21458, 21422, 21386, 21351, 21315, 21280, 21245, 21210, 21176, 21141,
    21107, 21073, 21039, 21005, 20972, 20938, 20905, 20872, 20839, 20806, 20773, 20741,
    20708, 20676, 20644, 20612, 20580, 20548, 20517, 20486, 20454, 20423, 20392, 20362,
    20331, 20301, 20270, 20240, 20210, 20180, 20150, 20120, 20091, 20061, 20032, 20003,
    19974, 19945, 19916, 19887, 19859, 19830, 19802, 19774, 19746, 19718, 19690, 19662,
    19635, 19607, 19580, 19553, 19526, 19498, 19472, 19445, 19418, 19391, 19365, 19339,
    19312, 19286, 19260, 19234, 19208, 19183, 19157, 19132, 19106, 19081, 19056, 19030,
    19005, 18980, 18956, 18931, 18906, 18882, 18857, 18833, 18809, 18785, 18760, 18737,
    18713, 18689, 18665, 18642, 18618, 18595, 18571, 18548, 18525, 18502, 18479, 18456,
    18433, 18410, 18388, 18365, 18343, 18320, 18298, 18276, 18253, 18231, 18209, 18187,
    18166, 18144, 18122, 18100, 18079, 18057, 18036, 18015, 17994, 17972, 17951, 17930,
    17909, 17888, 17868, 17847, 17826, 17806, 17785, 17765, 17744, 17724, 17704, 17684,
    17664, 17644, 17624, 17604, 17584, 17564, 17545, 17525, 17505, 17486, 17467, 17447,
    17428, 17409, 17390, 17370, 17351, 17332, 17314, 17295, 17276, 17257, 17238, 17220,
    17201, 17183, 17164, 17146, 17128, 17109, 17091, 17073, 17055, 17037, 17019, 17001,
    16983, 16966, 16948, 16930, 16913, 16895, 16877, 16860, 16843, 16825, 16808, 16791,
    16773, 16756, 16739, 16722, 16705, 16688, 16671, 16655, 16638, 16621, 16604, 16588,
    16571, 16555, 16538, 16522, 16505, 16489, 16473, 16456, 16440, 16424, 16408, 16392,
};

uint64_t psc_rsqrt46(uint64_t v)
{
    if (v == 0)
        return UINT64_MAX;
    /* v = m 2^e with e even and m in [2^30, 2^32): 1/sqrt(v) = 2^(-e/2) / sqrt(m). */
    int e = (int)bit_length(v) - 31;
    e -= e & 1;
    uint64_t m = e >= 0 ? v >> e : v << -e;
    /* y ~ 2^46 / sqrt(m) (Q30 of 1/sqrt(m / 2^32)) from the table, then one Newton step
     * y' = y (3 - M y^2) / 2 with M = m / 2^32: the table's error (at most 2^-9) becomes 1.5 (2^-9)^2 < 2^-17. */
    uint64_t y = (uint64_t)rsqrt_mantissa_q14[(m >> 23) - 128u] << 16;
    uint64_t y2 = (y * y) >> 30;                  /* Q30, < 2^32 */
    uint64_t my2 = ((m >> 2) * y2) >> 30;         /* Q30: M y^2 ~ 1 */
    y = (y * ((UINT64_C(3) << 30) - my2)) >> 31;  /* y < 2^31, 3 - M y^2 < 2^32 */
    if (e <= 0)
        return y << (-e / 2);
    return (y + ((uint64_t)1 << (e / 2 - 1))) >> (e / 2);
}

uint32_t psc_rsqrt_q30(uint32_t x)
{
    if (x == 0)
        return UINT32_MAX;
    return (uint32_t)((psc_rsqrt46(x) + 32768u) >> 16); /* 2^46 / sqrt(x) <= 2^46: 2^30 / sqrt(x) fits */
}

void psc_unit3_q16(const int64_t v[3], int32_t out[3])
{
    uint64_t m = 0;
    for (unsigned a = 0; a < 3; a++) {
        uint64_t x = v[a] < 0 ? 0u - (uint64_t)v[a] : (uint64_t)v[a];
        m = x > m ? x : m;
    }
    unsigned sh = 0;
    while ((m >> sh) >= (UINT64_C(1) << 30))
        sh++;
    int64_t s[3];
    uint64_t len2 = 0;   /* three squares under 2^60 */
    for (unsigned a = 0; a < 3; a++) {
        s[a] = v[a] >> sh;
        len2 += (uint64_t)(s[a] * s[a]);
    }
    /* |s[a]| x 2^46 / |s| <= 2^46 */
    uint64_t inv = len2 != 0 ? psc_rsqrt46(len2) : 0;
    for (unsigned a = 0; a < 3; a++)
        out[a] = (int32_t)psc_shr_round64(s[a] * (int64_t)inv, 30);
}
