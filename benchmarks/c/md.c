/* The work of particles.md.simulate_cooling / simulate_heated (hard rods of length
 * 0.5/n, constant alpha, default options) as a careful C program, for
 * benchmarks/bench_end_to_end.py.
 *
 * Same scheme as particles._md_kernels: rods mapped to points on the reduced ring of length
 * L - N sigma, lazily stored positions (x_i + v_i (t - tl_i)), one predicted time per
 * neighbour pair in an indexed binary min-heap (the Python kernel uses a 4-ary heap),
 * three pair times updated per collision; collisions with relative speed below the
 * threshold are elastic.  Heated: every kick interval (0.1 estimated mean free times) all
 * rods are moved to the kick time, kicked by white noise (the ziggurat of dsmc.c
 * replaced by Box-Muller pairs: same cost order) and the heap rebuilt by heapify; a sample
 * (histogram of v on +-12 sqrt(T), power sums to 12) every estimated mean free time.
 * Runs until `collisions` collisions are done; prints "collisions seconds checksum".
 *
 * usage: md cooling N alpha collisions seed threshold
 *        md heated  N alpha collisions seed threshold T_est
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static uint64_t s[4];
static inline uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
static inline uint64_t next(void) {
    uint64_t r = rotl(s[1] * 5, 7) * 9, t = s[1] << 17;
    s[2] ^= s[0]; s[3] ^= s[1]; s[1] ^= s[2]; s[0] ^= s[3]; s[2] ^= t; s[3] = rotl(s[3], 45);
    return r;
}
static inline double unif(void) { return ((next() >> 11) + 0.5) * (1.0 / 9007199254740992.0); }
static uint64_t splitmix(uint64_t *x) {
    uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL; z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}
static void normals(double *out, long n) {
    for (long k = 0; k < n; k += 2) {
        double r = sqrt(-2.0 * log(unif())), ph = 2.0 * M_PI * unif();
        out[k] = r * cos(ph); if (k + 1 < n) out[k + 1] = r * sin(ph);
    }
}

static long N; static double Lf;
static double *x, *v, *tl, *key; static long *heap, *where; static long hsize;

static inline void hswap(long a, long b) {
    long pa = heap[a], pb = heap[b]; heap[a] = pb; heap[b] = pa; where[pb] = a; where[pa] = b;
}
static void sift_up(long k) {
    while (k > 0) { long p = (k - 1) / 2; if (key[heap[p]] <= key[heap[k]]) break;
        hswap(p, k); k = p; }
}
static void sift_down(long k) {
    for (;;) { long c = 2 * k + 1, m = k;
        if (c < hsize && key[heap[c]] < key[heap[m]]) m = c;
        if (c + 1 < hsize && key[heap[c + 1]] < key[heap[m]]) m = c + 1;
        if (m == k) return;
        hswap(k, m); k = m; }
}
static inline double pair_time(long p, double t) {
    long i = p, j = p + 1 == N ? 0 : p + 1;
    double g = v[i] - v[j];
    if (!(g > 0)) return INFINITY;
    double yi = x[i] + v[i] * (t - tl[i]), yj = x[j] + v[j] * (t - tl[j]);
    if (p == N - 1) yj += Lf;
    double dt = (yj - yi) / g;
    return t + (dt > 0 ? dt : 0.0);
}
static void update(long p, double t) {
    double k = pair_time(p, t), old = key[p]; key[p] = k;
    if (k < old) sift_up(where[p]); else sift_down(where[p]);
}
static void rebuild(double t) {
    for (long p = 0; p < N; p++) { key[p] = pair_time(p, t); heap[p] = p; where[p] = p; }
    hsize = N;
    for (long k = N / 2; k >= 0; k--) sift_down(k);
}
static double now(void) { struct timespec q; clock_gettime(CLOCK_MONOTONIC, &q);
    return q.tv_sec + 1e-9 * q.tv_nsec; }

int main(int argc, char **argv) {
    if (argc < 7) { fprintf(stderr, "usage: see source\n"); return 2; }
    int heated = strcmp(argv[1], "heated") == 0;
    N = atol(argv[2]); double alpha = atof(argv[3]); long total = atol(argv[4]);
    uint64_t seed = strtoull(argv[5], 0, 10); double thr = atof(argv[6]);
    double T = heated ? atof(argv[7]) : 1.0;
    double t0 = now();
    for (int k = 0; k < 4; k++) s[k] = splitmix(&seed);
    Lf = 0.5 * N;  /* n = 1, sigma = 0.5: L - N sigma */
    x = malloc(N * 8); v = malloc(N * 8); tl = calloc(N, 8); key = malloc(N * 8);
    heap = malloc(N * 8); where = malloc(N * 8);
    double *xi = malloc((N + 1) * 8);
    normals(v, N);
    double mean = 0; for (long i = 0; i < N; i++) mean += v[i]; mean /= N;
    for (long i = 0; i < N; i++) { v[i] = (v[i] - mean) * sqrt(T); x[i] = (i + 0.5 * unif()) * Lf / N; }
    double tau = 1.0 / (2.0 * 2.0 * sqrt(T / M_PI));  /* n_f = 2 */
    double dtk = 0.1 * tau, amp = sqrt(2.0 * dtk), hw = 12.0 * sqrt(T);
    double t_kick = heated ? dtk : INFINITY, t_sample = heated ? tau : INFINITY;
    int bins = 240; double *counts = calloc(bins, 8), sums[13] = {0};
    double half = 0.5 * (1.0 + alpha), t = 0.0, chk = 0.0;
    long coll = 0;
    rebuild(0.0);
    while (coll < total) {
        long p = heap[0]; double tc = key[p];
        if (t_sample <= tc && t_sample <= t_kick) {  /* sample: all velocities */
            double w = (2 * hw) / bins;
            for (long i = 0; i < N; i++) { double q = v[i], pw = 1.0;
                for (int m = 0; m <= 12; m++) { sums[m] += pw; pw *= q; }
                long b = (long)floor((q + hw) / w); if (b >= 0 && b < bins) counts[b] += 1; }
            t_sample += tau; continue;
        }
        if (t_kick <= tc) {  /* kick: move all, add normals, rebuild */
            t = t_kick; normals(xi, N);
            for (long i = 0; i < N; i++) { x[i] += v[i] * (t - tl[i]); tl[i] = t;
                v[i] += amp * xi[i]; }
            rebuild(t); t_kick += dtk; continue;
        }
        t = tc;
        long i = p, j = p + 1 == N ? 0 : p + 1;
        x[i] += v[i] * (t - tl[i]); tl[i] = t; x[j] += v[j] * (t - tl[j]); tl[j] = t;
        double g = v[i] - v[j];
        if (g < thr) { double q = v[i]; v[i] = v[j]; v[j] = q; }
        else { double dv = half * g; v[i] -= dv; v[j] += dv; chk += g * g; }
        coll++;
        update(p, t); update(p == 0 ? N - 1 : p - 1, t); update(p + 1 == N ? 0 : p + 1, t);
    }
    printf("%ld %.6f %.6g\n", coll, now() - t0, chk * 1e-30 + counts[bins / 2] * 1e-30 + t);
    return 0;
}
