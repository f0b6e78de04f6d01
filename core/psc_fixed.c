/*
 * psc_fixed.c - integer square root, rounded division and CORDIC trigonometry.
 *
 * CORDIC runs on 64-bit integers with the operands normalised to about 2^61,
 * so the shift truncations are far below the result's last bit; 40 iterations
 * leave a residual angle far under one binary-angle unit. Right shifts of negative
 * values are arithmetic on every compiler Periscope supports (gcc, clang).
 */
#include "psc_fixed.h"

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

static unsigned bit_length(uint64_t v)
{
    unsigned n = 0;
    while (v) {
        n++;
        v >>= 1;
    }
    return n;
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
