// The frictionless pair blocks' contact test on this processor (BENCHMARKS.md, "Why fewer
// instructions cost wall time"): per row i, its listed partners j tested for
// |x_j - x_i|^2 < (R_i + R_j)^2 and a touching pair given a square root and a division, as
//   scalar:  one pair at a time with a branch (the pair loop of dynamics/contacts.rs);
//   gathers: four at a time, the partners' x, y, z, R by masked AVX2 gathers and the row's
//            last lanes masked (the scheme of commit 922d37a, reverted);
//   loads:   the same lanes from scalar loads instead of gathers;
//   quads:   a row's full groups of four from 16-byte (x, y) and 8-byte (z, R) loads, its last
//            1-3 pairs one at a time (the scheme of Rows::near4);
//   qtail:   quads with the last 1-3 pairs as a group of four, the lanes past the row masked.
// 10,000 rows of 3-6 partners (mean 4.5) within 60 bodies after i (a cell-sorted list); the
// first argument sets how many pairs touch; a second argument `periodic` gives the rows the
// lengths 3, 4, 5, 6 in turn instead of at random (the same mix, the loop exits predictable:
// what the row lengths' unpredictability costs). Prints ns per listed pair, best of 30 passes.
//   cc -O2 -o pair_test_lanes bench/pair_test_lanes.c -lm && ./pair_test_lanes 0.004 [periodic]
#include <immintrin.h>
#include <stdio.h>
#include <stdlib.h>
#include <stdint.h>
#include <time.h>
#define N 10000
static double pos[3 * N], rad[N];
static uint32_t start[N + 1], js[8 * N];
static double now(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
static inline double touchw(int i, int j) { // the work a touching pair adds (a sqrt and a division)
  double d0 = pos[3*j]-pos[3*i], d1 = pos[3*j+1]-pos[3*i+1], d2 = pos[3*j+2]-pos[3*i+2];
  double r = __builtin_sqrt(d0*d0+d1*d1+d2*d2); return (rad[i]+rad[j]-r) / r; }
__attribute__((noinline)) double scalar(void) {
  double acc = 0;
  for (int i = 0; i < N; i++) {
    double xi = pos[3*i], yi = pos[3*i+1], zi = pos[3*i+2], ri = rad[i];
    for (uint32_t k = start[i]; k < start[i+1]; k++) {
      uint32_t j = js[k];
      double d0 = pos[3*j]-xi, d1 = pos[3*j+1]-yi, d2 = pos[3*j+2]-zi, s = ri + rad[j];
      if (d0*d0 + d1*d1 + d2*d2 < s*s) acc += touchw(i, j);
    }
  }
  return acc;
}
__attribute__((noinline, target("avx2"))) double gathered(void) {
  double acc = 0;
  for (int i = 0; i < N; i++) {
    __m256d xi = _mm256_set1_pd(pos[3*i]), yi = _mm256_set1_pd(pos[3*i+1]), zi = _mm256_set1_pd(pos[3*i+2]), ri = _mm256_set1_pd(rad[i]);
    uint32_t e = start[i+1];
    for (uint32_t k = start[i]; k < e; k += 4) {
      int left = e - k < 4 ? e - k : 4;
      __m128i lanes = _mm_cmpgt_epi32(_mm_set1_epi32(left), _mm_setr_epi32(0,1,2,3));
      __m256d wide = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(lanes));
      __m128i j = _mm_maskload_epi32((const int*)(js + k), lanes);
      __m128i j3 = _mm_add_epi32(_mm_add_epi32(j, j), j);
      __m256d z = _mm256_setzero_pd();
      __m256d xj = _mm256_mask_i32gather_pd(z, pos, j3, wide, 8);
      __m256d yj = _mm256_mask_i32gather_pd(z, pos+1, j3, wide, 8);
      __m256d zj = _mm256_mask_i32gather_pd(z, pos+2, j3, wide, 8);
      __m256d rj = _mm256_mask_i32gather_pd(z, rad, j, wide, 8);
      __m256d d0 = _mm256_sub_pd(xj, xi), d1 = _mm256_sub_pd(yj, yi), d2 = _mm256_sub_pd(zj, zi);
      __m256d r2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(d0,d0), _mm256_mul_pd(d1,d1)), _mm256_mul_pd(d2,d2));
      __m256d s = _mm256_add_pd(ri, rj);
      unsigned near = _mm256_movemask_pd(_mm256_cmp_pd(r2, _mm256_mul_pd(s, s), _CMP_LT_OQ)) & ((1u << left) - 1);
      while (near) { int l = __builtin_ctz(near); near &= near - 1; acc += touchw(i, js[k + l]); }
    }
  }
  return acc;
}
__attribute__((noinline, target("avx2"))) double loaded(void) {
  double acc = 0;
  for (int i = 0; i < N; i++) {
    __m256d xi = _mm256_set1_pd(pos[3*i]), yi = _mm256_set1_pd(pos[3*i+1]), zi = _mm256_set1_pd(pos[3*i+2]), ri = _mm256_set1_pd(rad[i]);
    uint32_t e = start[i+1];
    for (uint32_t k = start[i]; k < e; k += 4) {
      int left = e - k < 4 ? e - k : 4;
      uint32_t j[4]; for (int l = 0; l < 4; l++) j[l] = js[k + (l < left ? l : 0)];
      __m256d xj = _mm256_setr_pd(pos[3*j[0]], pos[3*j[1]], pos[3*j[2]], pos[3*j[3]]);
      __m256d yj = _mm256_setr_pd(pos[3*j[0]+1], pos[3*j[1]+1], pos[3*j[2]+1], pos[3*j[3]+1]);
      __m256d zj = _mm256_setr_pd(pos[3*j[0]+2], pos[3*j[1]+2], pos[3*j[2]+2], pos[3*j[3]+2]);
      __m256d rj = _mm256_setr_pd(rad[j[0]], rad[j[1]], rad[j[2]], rad[j[3]]);
      __m256d d0 = _mm256_sub_pd(xj, xi), d1 = _mm256_sub_pd(yj, yi), d2 = _mm256_sub_pd(zj, zi);
      __m256d r2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(d0,d0), _mm256_mul_pd(d1,d1)), _mm256_mul_pd(d2,d2));
      __m256d s = _mm256_add_pd(ri, rj);
      unsigned near = _mm256_movemask_pd(_mm256_cmp_pd(r2, _mm256_mul_pd(s, s), _CMP_LT_OQ)) & ((1u << left) - 1);
      while (near) { int l = __builtin_ctz(near); near &= near - 1; acc += touchw(i, js[k + l]); }
    }
  }
  return acc;
}
__attribute__((noinline, target("avx2"))) double quads(void) {
  // Full groups of four from 128-bit (x, y) loads and scalar z, r; the last 1-3 pairs one at a time.
  double acc = 0;
  for (int i = 0; i < N; i++) {
    double xs = pos[3*i], ys = pos[3*i+1], zs = pos[3*i+2], rs = rad[i];
    __m256d xi = _mm256_set1_pd(xs), yi = _mm256_set1_pd(ys), zi = _mm256_set1_pd(zs), ri = _mm256_set1_pd(rs);
    uint32_t k = start[i], e = start[i+1];
    for (; k + 4 <= e; k += 4) {
      uint32_t j0 = js[k], j1 = js[k+1], j2 = js[k+2], j3 = js[k+3];
      __m256d a = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(pos+3*j0)), _mm_loadu_pd(pos+3*j2), 1);
      __m256d b = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(pos+3*j1)), _mm_loadu_pd(pos+3*j3), 1);
      __m256d xj = _mm256_unpacklo_pd(a, b), yj = _mm256_unpackhi_pd(a, b);
      __m128d z01 = _mm_loadh_pd(_mm_load_sd(pos+3*j0+2), pos+3*j1+2), z23 = _mm_loadh_pd(_mm_load_sd(pos+3*j2+2), pos+3*j3+2);
      __m128d r01 = _mm_loadh_pd(_mm_load_sd(rad+j0), rad+j1), r23 = _mm_loadh_pd(_mm_load_sd(rad+j2), rad+j3);
      __m256d zj = _mm256_insertf128_pd(_mm256_castpd128_pd256(z01), z23, 1), rj = _mm256_insertf128_pd(_mm256_castpd128_pd256(r01), r23, 1);
      __m256d d0 = _mm256_sub_pd(xj, xi), d1 = _mm256_sub_pd(yj, yi), d2 = _mm256_sub_pd(zj, zi);
      __m256d r2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(d0,d0), _mm256_mul_pd(d1,d1)), _mm256_mul_pd(d2,d2));
      __m256d s = _mm256_add_pd(ri, rj);
      unsigned near = _mm256_movemask_pd(_mm256_cmp_pd(r2, _mm256_mul_pd(s, s), _CMP_NGE_UQ));
      while (near) { int l = __builtin_ctz(near); near &= near - 1; acc += touchw(i, js[k + l]); }
    }
    for (; k < e; k++) {
      uint32_t j = js[k];
      double d0 = pos[3*j]-xs, d1 = pos[3*j+1]-ys, d2 = pos[3*j+2]-zs, s = rs + rad[j];
      if (d0*d0 + d1*d1 + d2*d2 < s*s) acc += touchw(i, j);
    }
  }
  return acc;
}
__attribute__((noinline, target("avx2"))) double qtail(void) {
  // As quads, the last 1-3 pairs as a group of four with the lanes past the row masked off.
  double acc = 0;
  for (int i = 0; i < N; i++) {
    double xs = pos[3*i], ys = pos[3*i+1], zs = pos[3*i+2], rs = rad[i];
    __m256d xi = _mm256_set1_pd(xs), yi = _mm256_set1_pd(ys), zi = _mm256_set1_pd(zs), ri = _mm256_set1_pd(rs);
    uint32_t k = start[i], e = start[i+1];
    for (; k < e; k += 4) {
      unsigned lanes = (1u << (e - k < 4 ? e - k : 4)) - 1;
      uint32_t j0 = js[k], j1 = js[k+1], j2 = js[k+2], j3 = js[k+3];
      __m256d a = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(pos+3*j0)), _mm_loadu_pd(pos+3*j2), 1);
      __m256d b = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(pos+3*j1)), _mm_loadu_pd(pos+3*j3), 1);
      __m256d xj = _mm256_unpacklo_pd(a, b), yj = _mm256_unpackhi_pd(a, b);
      __m128d z01 = _mm_loadh_pd(_mm_load_sd(pos+3*j0+2), pos+3*j1+2), z23 = _mm_loadh_pd(_mm_load_sd(pos+3*j2+2), pos+3*j3+2);
      __m128d r01 = _mm_loadh_pd(_mm_load_sd(rad+j0), rad+j1), r23 = _mm_loadh_pd(_mm_load_sd(rad+j2), rad+j3);
      __m256d zj = _mm256_insertf128_pd(_mm256_castpd128_pd256(z01), z23, 1), rj = _mm256_insertf128_pd(_mm256_castpd128_pd256(r01), r23, 1);
      __m256d d0 = _mm256_sub_pd(xj, xi), d1 = _mm256_sub_pd(yj, yi), d2 = _mm256_sub_pd(zj, zi);
      __m256d r2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(d0,d0), _mm256_mul_pd(d1,d1)), _mm256_mul_pd(d2,d2));
      __m256d s = _mm256_add_pd(ri, rj);
      unsigned near = _mm256_movemask_pd(_mm256_cmp_pd(r2, _mm256_mul_pd(s, s), _CMP_NGE_UQ)) & lanes;
      while (near) { int l = __builtin_ctz(near); near &= near - 1; acc += touchw(i, js[k + l]); }
    }
    for (; k < e; k++) {
      uint32_t j = js[k];
      double d0 = pos[3*j]-xs, d1 = pos[3*j+1]-ys, d2 = pos[3*j+2]-zs, s = rs + rad[j];
      if (d0*d0 + d1*d1 + d2*d2 < s*s) acc += touchw(i, j);
    }
  }
  return acc;
}
int main(int argc, char **argv) {
  double touch = argc > 1 ? atof(argv[1]) : 0.07; int periodic = argc > 2 && argv[2][0] == 'p';
  srand(1);
  for (int i = 0; i < N; i++) { pos[3*i] = i * 1.0; pos[3*i+1] = 0; pos[3*i+2] = 0; rad[i] = 0.5; }
  uint32_t k = 0; long touching = 0;
  for (int i = 0; i < N; i++) {
    start[i] = k; int len = periodic ? 3 + i % 4 : 3 + rand() % 4;
    for (int l = 0; l < len; l++) {
      uint32_t j = i + 1 + rand() % 60;
      if (j < N) js[k++] = j;
    }
  }
  start[N] = k;
  // Touching: a share of the pairs get the partner's radius grown to reach.
  for (uint32_t q = 0; q < k; q++) if (rand() < touch * RAND_MAX) { rad[js[q]] = 100.0; }
  for (int i = 0; i < N; i++) for (uint32_t q = start[i]; q < start[i+1]; q++) { uint32_t j = js[q]; double d = pos[3*j]-pos[3*i], s = rad[i]+rad[j]; touching += d*d < s*s; }
  int chunks = 0; for (int i = 0; i < N; i++) chunks += (start[i+1]-start[i]+3)/4;
  printf("pairs %u, rows %d, touching %.3f, four-lane chunks %d (lanes used %.3f)\n", k, N, (double)touching/k, chunks, (double)k/(4.0*chunks));
  double (*f[5])(void) = {scalar, gathered, loaded, quads, qtail}; const char *name[5] = {"scalar", "gathers", "loads", "quads", "qtail"};
  double best[5] = {1e9, 1e9, 1e9, 1e9, 1e9}, chk[5];
  for (int rep = 0; rep < 30; rep++) for (int v = 0; v < 5; v++) {
    double t = now(); chk[v] = f[v](); t = now() - t; if (t < best[v]) best[v] = t; }
  for (int v = 0; v < 5; v++) printf("%-8s %.2f ns a listed pair (best of 30), check %.6g\n", name[v], 1e9 * best[v] / k, chk[v]);
  return 0;
}
