/* Shared by the C programs of benchmarks/bench_end_to_end.py: xoshiro256** (state in
 * the global s, or in locals s0..s3 with LOAD/NEXT/STORE) and the 256-layer normal
 * ziggurat with the tables of particles.rng.ziggurat_tables. */
#include <math.h>
#include <stdint.h>
#include <time.h>
static uint64_t s[4];
static inline uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
static inline uint64_t next(void) {
    uint64_t r = rotl(s[1] * 5, 7) * 9, t = s[1] << 17;
    s[2] ^= s[0]; s[3] ^= s[1]; s[1] ^= s[2]; s[0] ^= s[3]; s[2] ^= t; s[3] = rotl(s[3], 45);
    return r;
}
/* xoshiro256** on the state in local variables s0..s3 (kept in registers in the loops) */
#define NEXT(r) do { uint64_t t_ = s1 << 17; r = rotl(s1 * 5, 7) * 9; s2 ^= s0; s3 ^= s1; \
    s1 ^= s2; s0 ^= s3; s2 ^= t_; s3 = rotl(s3, 45); } while (0)
#define LOAD uint64_t s0 = s[0], s1 = s[1], s2 = s[2], s3 = s[3]
#define STORE do { s[0] = s0; s[1] = s1; s[2] = s2; s[3] = s3; } while (0)
static inline double next_double(void) { return (next() >> 11) * (1.0 / 9007199254740992.0); }
static uint64_t splitmix(uint64_t *x) {
    uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL; z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* ziggurat tables as particles.rng.ziggurat_tables */
static uint64_t ki[256]; static double wi[512], fi[256];
#define ZR 3.6541528853610088
static void zig_init(void) {
    double dn = ZR, tn = ZR, V = 0.00492867323399, M1 = 4503599627370496.0;
    double q = V / exp(-0.5 * dn * dn);
    ki[0] = (uint64_t)((dn / q) * M1); ki[1] = 0; wi[0] = q / M1; wi[255] = dn / M1;
    fi[0] = 1.0; fi[255] = exp(-0.5 * dn * dn);
    for (int i = 254; i >= 1; i--) {
        dn = sqrt(-2.0 * log(V / dn + exp(-0.5 * dn * dn)));
        ki[i + 1] = (uint64_t)((dn / tn) * M1); tn = dn; fi[i] = exp(-0.5 * dn * dn);
        wi[i] = dn / M1;
    }
    for (int i = 0; i < 256; i++) wi[256 + i] = -wi[i];
}
static double normal_slow(int idx, double x) {
    for (;;) {
        if (idx == 0) {
            for (;;) {
                double xx = -log1p(-next_double()) / ZR, yy = -log1p(-next_double());
                if (yy + yy > xx * xx) return x < 0 ? -(ZR + xx) : ZR + xx;
            }
        }
        if ((fi[idx - 1] - fi[idx]) * next_double() + fi[idx] < exp(-0.5 * x * x)) return x;
        uint64_t r = next(), ls = r & 0x1FF, rabs = (r >> 9) & 0x000FFFFFFFFFFFFFULL;
        idx = (int)(ls & 0xFF); x = (double)(int64_t)rabs * wi[ls];
        if (rabs < ki[idx]) return x;
    }
}
static inline double normal(void) {
    uint64_t r = next(), ls = r & 0x1FF, rabs = (r >> 9) & 0x000FFFFFFFFFFFFFULL;
    int idx = (int)(ls & 0xFF);
    double x = (double)(int64_t)rabs * wi[ls];
    if (__builtin_expect(rabs >= ki[idx], 0)) x = normal_slow(idx, x);
    return x;
}
static double now(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec; }
