/* The work of particles.dsmc.simulate_cooling / simulate_heated (hard rods, constant
 * alpha, default options) written as a careful C program, for benchmarks/bench_end_to_end.py.
 *
 * Same algorithm as the Python call: xoshiro256**, candidates from two draws (pair from
 * the high words of r1 N and r2 (N-1), acceptance uniform from the low word of r1 N),
 * branch-free collision; cooling: blocks of at most max(4N, 65536) candidates with a
 * rescaling to unit temperature every N candidates (sums and extent, then rescale) and a
 * central rescale after each block, a measurement every N/2 collisions (central moments
 * up to 6 and a 240-bin histogram of c = v/sqrt(<v^2>) with power sums up to 12);
 * heated: Strang steps of white-noise kicks (256-layer ziggurat, the same tables) and
 * collisions, 0.05 mean free times per step, a measurement every collision per particle
 * (central moments up to 6, 200-bin histogram, power sums up to 12).
 * heated-wy: the scheme of the Python call since issue 13 (particles/_dsmc_heated.py): the
 * kicks' normals take their 64 bits from wyrand (the ziggurat's slow paths from
 * xoshiro256**), each candidate is one wyrand draw (pair from the high words of r N and
 * low(r N) (N-1), acceptance uniform from the last low word), and a measurement is two
 * passes (mean; centring, moments, histogram and power sums together).
 * Runs until `collisions` collisions are done; prints "collisions seconds checksum".
 * The optional last argument `every` (default 1) measures every `every` collisions per
 * particle instead: the averaging cadence the Python call chose (it measures every
 * collision per particle until relaxation and over its first batch, so the C program
 * then does less measuring than the Python call).
 *
 * usage: dsmc cooling N alpha collisions seed [every]
 *        dsmc heated  N alpha collisions seed T_ref [every]
 *        dsmc heated-wy N alpha collisions seed T_ref [every]
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "common.h"
#define KMAX 12
/* white-noise kick, returns the extent */
static double kick(double *v, long n, double amp) {
    double lo = INFINITY, hi = -INFINITY;
    LOAD;
    for (long k = 0; k < n; k++) {
        uint64_t r; NEXT(r);
        uint64_t ls = r & 0x1FF, rabs = (r >> 9) & 0x000FFFFFFFFFFFFFULL;
        int idx = (int)(ls & 0xFF);
        double x = (double)(int64_t)rabs * wi[ls];
        if (__builtin_expect(rabs >= ki[idx], 0)) {
            STORE; x = normal_slow(idx, x); s0 = s[0]; s1 = s[1]; s2 = s[2]; s3 = s[3];
        }
        double y = v[k] + amp * x;
        v[k] = y; lo = y < lo ? y : lo; hi = y > hi ? y : hi;
    }
    STORE;
    return hi - lo;
}

/* wyrand: a Weyl counter mixed by one 64 x 64 -> 128-bit multiply */
static uint64_t wst;
#define WY(r, w) do { w += 0xa0761d6478bd642fULL; \
    unsigned __int128 p_ = (unsigned __int128)w * (w ^ 0xe7037ed1a0b428dbULL); \
    r = (uint64_t)(p_ >> 64) ^ (uint64_t)p_; } while (0)
static double kick_wy(double *v, long n, double amp) {
    double lo = INFINITY, hi = -INFINITY;
    uint64_t w = wst;
    for (long k = 0; k < n; k++) {
        uint64_t r; WY(r, w);
        uint64_t ls = r & 0x1FF, rabs = (r >> 9) & 0x000FFFFFFFFFFFFFULL;
        int idx = (int)(ls & 0xFF);
        double x = (double)(int64_t)rabs * wi[ls];
        if (__builtin_expect(rabs >= ki[idx], 0)) x = normal_slow(idx, x);  /* xoshiro */
        double y = v[k] + amp * x;
        v[k] = y; lo = y < lo ? y : lo; hi = y > hi ? y : hi;
    }
    wst = w;
    return hi - lo;
}
static long collide_wy(double *v, uint64_t n, long m, double half, double gmax) {
    uint64_t n1 = n - 1, w = wst; double scale = gmax / 9007199254740992.0; long acc = 0;
    for (long c = 0; c < m; c++) {
        uint64_t r; WY(r, w);
        unsigned __int128 p1 = (unsigned __int128)r * n;
        uint64_t i = (uint64_t)(p1 >> 64);
        unsigned __int128 p2 = (unsigned __int128)(uint64_t)p1 * n1;
        uint64_t j = (uint64_t)(p2 >> 64), low = (uint64_t)p2;
        j += (j >= i);
        double thr = (double)(int64_t)(low >> 11) * scale;
        double vi = v[i], vj = v[j], g = vi - vj;
        int a = fabs(g) > thr;
        double dv = a ? half * g : 0.0;
        v[i] = vi - dv; v[j] = vj + dv; acc += a;
    }
    wst = w;
    return acc;
}
/* mean; then centring, central moments 0..6, histogram and power sums to 12 in one pass */
static void measure_fused(double *v, long n, double lo, double hi, double *counts, int bins,
                          double *sums, double *cm) {
    double a[4] = {0}, p[KMAX + 1] = {0};
    long k;
    for (k = 0; k + 4 <= n; k += 4) for (int l = 0; l < 4; l++) a[l] += v[k + l];
    for (; k < n; k++) a[0] += v[k];
    double mean = ((a[0] + a[1]) + (a[2] + a[3])) / n, inv = bins / (hi - lo);
    for (k = 0; k < n; k++) {
        double x = v[k] - mean, q = 1.0;
        v[k] = x;
        for (int m = 0; m <= KMAX; m++) { p[m] += q; q *= x; }
        double b = floor((x - lo) * inv);
        if (b >= 0 && b < bins) counts[(long)b] += 1.0;
    }
    for (int m = 0; m <= KMAX; m++) sums[m] += p[m];
    for (int m = 0; m <= 6; m++) cm[m] = p[m] / n;
}

static long collide(double *v, uint64_t n, long m, double half, double gmax) {
    uint64_t n1 = n - 1; double scale = gmax / 9007199254740992.0; long acc = 0;
    LOAD;
    for (long c = 0; c < m; c++) {
        uint64_t r1, r2; NEXT(r1); NEXT(r2);
        unsigned __int128 p1 = (unsigned __int128)r1 * n;
        uint64_t i = (uint64_t)(p1 >> 64), low = (uint64_t)p1;
        uint64_t j = (uint64_t)(((unsigned __int128)r2 * n1) >> 64);
        j += (j >= i);
        double thr = (double)(int64_t)(low >> 11) * scale;
        double vi = v[i], vj = v[j], g = vi - vj;
        int a = fabs(g) > thr;
        double dv = a ? half * g : 0.0;
        v[i] = vi - dv; v[j] = vj + dv; acc += a;
    }
    STORE;
    return acc;
}

/* central moments 0..6 (four lanes), subtract the mean */
static void centre(double *v, long n, double *cm) {
    double a[4] = {0}, mean;
    long k;
    for (k = 0; k + 4 <= n; k += 4) for (int l = 0; l < 4; l++) a[l] += v[k + l];
    for (; k < n; k++) a[0] += v[k];
    mean = ((a[0] + a[1]) + (a[2] + a[3])) / n;
    double acc[7][4] = {{0}};
    for (k = 0; k + 4 <= n; k += 4)
        for (int l = 0; l < 4; l++) {
            double d = v[k + l] - mean, p = 1.0;
            for (int m = 0; m <= 6; m++) { acc[m][l] += p; p *= d; }
        }
    for (; k < n; k++) { double d = v[k] - mean, p = 1.0;
        for (int m = 0; m <= 6; m++) { acc[m][0] += p; p *= d; } }
    for (int m = 0; m <= 6; m++) cm[m] = ((acc[m][0] + acc[m][1]) + (acc[m][2] + acc[m][3])) / n;
    for (k = 0; k < n; k++) v[k] -= mean;
}
static void accumulate(const double *v, long n, double scale, double lo, double hi,
                       double *counts, int bins, double *sums) {
    double width = (hi - lo) / bins;
    for (long k = 0; k < n; k++) {
        double x = v[k] * scale, p = 1.0;
        for (int m = 0; m <= KMAX; m++) { sums[m] += p; p *= x; }
        long b = (long)floor((x - lo) / width);
        if (b >= 0 && b < bins) counts[b] += 1.0;
    }
}


int main(int argc, char **argv) {
    if (argc < 6) { fprintf(stderr, "usage: see source\n"); return 2; }
    int wy = strcmp(argv[1], "heated-wy") == 0;
    int heated = wy || strcmp(argv[1], "heated") == 0;
    long n = atol(argv[2]); double alpha = atof(argv[3]);
    long total = atol(argv[4]); uint64_t seed = strtoull(argv[5], 0, 10);
    double t_ref = heated ? atof(argv[6]) : 1.0;
    int every_arg = heated ? 7 : 6;
    long every = argc > every_arg ? atol(argv[every_arg]) : 1;
    if (every < 1) every = 1;
    double t0 = now();
    for (int k = 0; k < 4; k++) s[k] = splitmix(&seed);
    wst = splitmix(&seed);
    zig_init();
    double *v = malloc(n * sizeof(double));
    double sd = sqrt(t_ref);
    for (long k = 0; k < n; k++) v[k] = sd * normal();
    int bins = heated ? 200 : 240;
    double *counts = calloc(bins, sizeof(double)), sums[KMAX + 1] = {0}, cm[7];
    double half = 0.5 * (1.0 + alpha), chk = 0.0;
    long accepted = 0;
    if (wy) {
        double rate1 = 2.0 * sqrt(t_ref / M_PI);
        double dt = 0.05 / rate1, amp = sqrt(2.0 * dt), hamp = amp / sqrt(2.0);
        long steps = every * lround(1.0 / (dt * rate1));
        double rate = 0.5 * n, debt = 0.0, hw = 10.0 * sqrt(t_ref);
        while (accepted < total) {
            double gmax = kick_wy(v, n, hamp);
            for (long st = 0; st < steps; st++) {
                double x = debt + dt * rate * gmax; long m = (long)floor(x); debt = x - m;
                accepted += collide_wy(v, n, m, half, gmax);
                gmax = kick_wy(v, n, st < steps - 1 ? amp : hamp);
            }
            measure_fused(v, n, -hw, hw, counts, bins, sums, cm);
            chk += cm[4] / (3 * cm[2] * cm[2]) - 1.0;
        }
    } else if (heated) {
        double rate1 = 2.0 * sqrt(t_ref / M_PI);  /* n <|g|> at T_ref, n = 1 */
        double dt = 0.05 / rate1, amp = sqrt(2.0 * dt), hamp = amp / sqrt(2.0);
        long steps = every * lround(1.0 / (dt * rate1));
        double rate = 0.5 * n, debt = 0.0, hw = 10.0 * sqrt(t_ref);
        while (accepted < total) {
            double gmax = kick(v, n, hamp);
            for (long st = 0; st < steps; st++) {
                double x = debt + dt * rate * gmax; long m = (long)floor(x); debt = x - m;
                accepted += collide(v, n, m, half, gmax);
                gmax = kick(v, n, st < steps - 1 ? amp : hamp);
            }
            centre(v, n, cm); chk += cm[4] / (3 * cm[2] * cm[2]) - 1.0;
            accumulate(v, n, 1.0, -hw, hw, counts, bins, sums);
        }
    } else {
        long refresh = n, cand = 0;
        while (accepted < total) {
            long target = accepted + every * (n / 2 > 1 ? n / 2 : 1);
            while (accepted < target) {
                double ratio = cand ? (double)accepted / cand : 0.1;
                long need = (long)((target - accepted) / (ratio > 1e-3 ? ratio : 1e-3)) + 1;
                long lim = 4 * n > 65536 ? 4 * n : 65536, m = need < lim ? need : lim;
                for (long done = 0; done < m;) {
                    double s1 = 0, s2 = 0, lo = v[0], hi = v[0];
                    for (long k = 0; k < n; k++) { double x = v[k]; s1 += x; s2 += x * x;
                        lo = x < lo ? x : lo; hi = x > hi ? x : hi; }
                    double mean = s1 / n, inv = 1.0 / sqrt(s2 / n - mean * mean);
                    for (long k = 0; k < n; k++) v[k] = (v[k] - mean) * inv;
                    long mm = refresh < m - done ? refresh : m - done;
                    accepted += collide(v, n, mm, half, (hi - lo) * inv);
                    done += mm;
                }
                cand += m;
                centre(v, n, cm);
                double inv = 1.0 / sqrt(cm[2]);
                for (long k = 0; k < n; k++) v[k] *= inv;
            }
            centre(v, n, cm); chk += cm[4] / (3 * cm[2] * cm[2]) - 1.0;
            double ms = 0; for (long k = 0; k < n; k++) ms += v[k] * v[k];
            accumulate(v, n, 1.0 / sqrt(ms / n), -6.0, 6.0, counts, bins, sums);
        }
    }
    printf("%ld %.6f %.6g\n", accepted, now() - t0, chk + counts[bins / 2] * 1e-30);
    free(v); free(counts);
    return 0;
}
