/* The work of particles.md.simulate_cooling / simulate_heated (hard rods of length
 * 0.5/n, constant alpha, default options) as a careful C program, for
 * benchmarks/bench_end_to_end.py.
 *
 * Same scheme as particles._md_kernels: rods mapped to points on the reduced ring of length
 * L - N sigma, lazily stored positions (x_i + v_i (t - tl_i)), one predicted time per
 * neighbour pair in an indexed 4-ary min-heap that holds only the pairs meeting before
 * the next kick, three pair times updated per collision; collisions with relative speed
 * below the threshold are elastic.  Heated: every kick interval (0.1 estimated mean free
 * times) all rods are moved to the kick time and kicked by white noise (ziggurat normals,
 * common.h), the pairs meeting before the following kick are heapified; a sample
 * (histogram of v on +-12 sqrt(T), power sums to 12) every estimated mean free time.
 * Runs until `collisions` collisions are done; prints "collisions seconds checksum".
 *
 * usage: md cooling N alpha collisions seed threshold
 *        md heated  N alpha collisions seed threshold T_est
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common.h"

static long N; static double Lf, t_kick;
static double *x, *v, *tl, *key; static long *heap, *where; static long hsize;

static inline void place(long k, long p) { heap[k] = p; where[p] = k; }
static void sift_up(long k) {
    long p = heap[k]; double kp = key[p];
    while (k > 0) { long q = (k - 1) / 4; if (key[heap[q]] <= kp) break;
        place(k, heap[q]); k = q; }
    place(k, p);
}
static void sift_down(long k) {
    long p = heap[k]; double kp = key[p];
    for (;;) {
        long c = 4 * k + 1, m = -1; double km = kp;
        long e = c + 4 < hsize ? c + 4 : hsize;
        for (long q = c; q < e; q++) if (key[heap[q]] < km) { km = key[heap[q]]; m = q; }
        if (m < 0) break;
        place(k, heap[m]); k = m;
    }
    place(k, p);
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
    double k = pair_time(p, t);
    long w = where[p];
    if (k >= t_kick) {  /* not before the next kick: out of the heap */
        if (w >= 0) { where[p] = -1; hsize--;
            if (w < hsize) { long last = heap[hsize]; place(w, last);
                sift_up(w); sift_down(where[last]); } }
        key[p] = k; return;
    }
    key[p] = k;
    if (w < 0) { place(hsize, p); hsize++; sift_up(hsize - 1); }
    else { sift_up(w); sift_down(where[p]); }
}
static void rebuild(double t) {
    hsize = 0;
    for (long p = 0; p < N; p++) { key[p] = pair_time(p, t); where[p] = -1;
        if (key[p] < t_kick) place(hsize++, p); }
    for (long k = hsize / 4; k >= 0; k--) if (k < hsize) sift_down(k);
}

int main(int argc, char **argv) {
    if (argc < 7) { fprintf(stderr, "usage: see source\n"); return 2; }
    int heated = strcmp(argv[1], "heated") == 0;
    N = atol(argv[2]); double alpha = atof(argv[3]); long total = atol(argv[4]);
    uint64_t seed = strtoull(argv[5], 0, 10); double thr = atof(argv[6]);
    double T = heated ? atof(argv[7]) : 1.0;
    double t0 = now();
    for (int k = 0; k < 4; k++) s[k] = splitmix(&seed);
    zig_init();
    Lf = 0.5 * N;  /* n = 1, sigma = 0.5: L - N sigma */
    x = malloc(N * 8); v = malloc(N * 8); tl = calloc(N, 8); key = malloc(N * 8);
    heap = malloc(N * 8); where = malloc(N * 8);
    double mean = 0;
    for (long i = 0; i < N; i++) { v[i] = normal(); mean += v[i]; }
    mean /= N;
    for (long i = 0; i < N; i++) { v[i] = (v[i] - mean) * sqrt(T);
        x[i] = (i + 0.5 * next_double()) * Lf / N; }
    double tau = 1.0 / (2.0 * 2.0 * sqrt(T / M_PI));  /* n_f = 2 */
    double dtk = 0.1 * tau, amp = sqrt(2.0 * dtk), hw = 12.0 * sqrt(T);
    double t_sample = heated ? tau : INFINITY;
    t_kick = heated ? dtk : INFINITY;
    int bins = 240; double *counts = calloc(bins, 8), sums[13] = {0};
    double half = 0.5 * (1.0 + alpha), t = 0.0, chk = 0.0;
    long coll = 0;
    rebuild(0.0);
    while (coll < total) {
        double tc = hsize ? key[heap[0]] : INFINITY;
        if (t_sample <= tc && t_sample <= t_kick) {  /* sample: all velocities */
            double w = (2 * hw) / bins;
            for (long i = 0; i < N; i++) { double q = v[i], pw = 1.0;
                for (int m = 0; m <= 12; m++) { sums[m] += pw; pw *= q; }
                long b = (long)floor((q + hw) / w);
                if (b >= 0 && b < bins) counts[b] += 1; }
            t_sample += tau; continue;
        }
        if (t_kick <= tc) {  /* kick: move all, add normals, heapify the early pairs */
            t = t_kick;
            LOAD;
            for (long i = 0; i < N; i++) {
                uint64_t r; NEXT(r);
                uint64_t ls = r & 0x1FF, rabs = (r >> 9) & 0x000FFFFFFFFFFFFFULL;
                int idx = (int)(ls & 0xFF);
                double z = (double)(int64_t)rabs * wi[ls];
                if (__builtin_expect(rabs >= ki[idx], 0)) {
                    STORE; z = normal_slow(idx, z); s0 = s[0]; s1 = s[1]; s2 = s[2]; s3 = s[3];
                }
                x[i] += v[i] * (t - tl[i]); tl[i] = t; v[i] += amp * z;
            }
            STORE;
            t_kick += dtk; rebuild(t); continue;
        }
        long p = heap[0];
        t = tc;
        long i = p, j = p + 1 == N ? 0 : p + 1;
        x[i] += v[i] * (t - tl[i]); tl[i] = t; x[j] += v[j] * (t - tl[j]); tl[j] = t;
        double g = v[i] - v[j];
        if (g < thr) { double q = v[i]; v[i] = v[j]; v[j] = q; }
        else { double dv = half * g; v[i] -= dv; v[j] += dv; chk += g * g; }
        coll++;
        update(p, t); update(p == 0 ? N - 1 : p - 1, t); update(p + 1 == N ? 0 : p + 1, t);
    }
    double t2 = 0; for (long i = 0; i < N; i++) t2 += v[i] * v[i];
    printf("%ld %.6f %.6g %.6g\n", coll, now() - t0, chk * 1e-30 + counts[bins / 2] * 1e-30 + t,
           t2 / N);
    return 0;
}
