/* rnea_plugin.c: a method from outside, written against eigenmass_plugin.h
 * alone (none of eigenmass's own code): u' of a tree of hinges by the
 * textbook recursive Newton-Euler algorithm and a dense Cholesky solve.
 * Revolute joints, and universal and gimbal joints as two or three hinges
 * through massless links (their u is q', as a revolute's). One "link" below
 * per hinge: link k turns by q[k] and its speed is u[k].
 *
 *   bias  = RNEA(q, u, u' = 0, gravity)          (Coriolis, centrifugal, gravity)
 *   M e_k = RNEA(q, 0, u' = e_k, no gravity)     (column k of the mass matrix)
 *   M u'  = Q - bias + tau,  Q = -k (q - rest) - c u   (the joints' springs;
 *           tau: what eigenmass adds on a mechanism, its drives and point springs)
 *
 * O(n^2) RNEA passes and an O(n^3) solve: written for clarity, not speed.
 * Build: cc -O2 -shared -fPIC -I<eigenmass>/outside rnea_plugin.c -o librnea.so -lm
 * Use:   eigenmass compare scene.json --plugin rnea=./librnea.so
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "eigenmass_plugin.h"

typedef struct { double x[3]; } v3;

static v3 add(v3 a, v3 b) { v3 r = {{a.x[0] + b.x[0], a.x[1] + b.x[1], a.x[2] + b.x[2]}}; return r; }
static v3 sub(v3 a, v3 b) { v3 r = {{a.x[0] - b.x[0], a.x[1] - b.x[1], a.x[2] - b.x[2]}}; return r; }
static v3 scale(double s, v3 a) { v3 r = {{s * a.x[0], s * a.x[1], s * a.x[2]}}; return r; }
static double dot(v3 a, v3 b) { return a.x[0] * b.x[0] + a.x[1] * b.x[1] + a.x[2] * b.x[2]; }
static v3 cross(v3 a, v3 b) {
  v3 r = {{a.x[1] * b.x[2] - a.x[2] * b.x[1], a.x[2] * b.x[0] - a.x[0] * b.x[2], a.x[0] * b.x[1] - a.x[1] * b.x[0]}};
  return r;
}
/* y = R x and y = R^T x for a row-major 3x3 R. */
static v3 mul(const double* R, v3 x) {
  v3 r;
  for (int i = 0; i < 3; ++i) r.x[i] = R[3 * i] * x.x[0] + R[3 * i + 1] * x.x[1] + R[3 * i + 2] * x.x[2];
  return r;
}
static void matmul(const double* A, const double* B, double* C) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}
/* Rodrigues: the rotation by angle q about the unit axis a. */
static void rot(v3 a, double q, double* R) {
  const double c = cos(q), s = sin(q), t = 1 - c;
  const double x = a.x[0], y = a.x[1], z = a.x[2];
  const double M[9] = {t * x * x + c,     t * x * y - s * z, t * x * z + s * y,
                       t * x * y + s * z, t * y * y + c,     t * y * z - s * x,
                       t * x * z - s * y, t * y * z + s * x, t * z * z + c};
  memcpy(R, M, sizeof M);
}

typedef struct {
  int n;
  int* parent;
  double *mass, *J, *axis, *a, *c, *k, *damp, *rest; /* J: 9 per body (body frame); axis, a, c: 3 per body */
  double g[3];
  /* scratch, per body */
  double* R;                    /* 9: world <- body */
  v3 *z, *o, *r, *w, *v, *al, *ac, *F, *N;
  double *M, *bias, *L, *tau;
} rnea;

static v3 at3(const double* p, int i) { v3 r = {{p[3 * i], p[3 * i + 1], p[3 * i + 2]}}; return r; }

/* Kinematics at q: orientations, world axes, joint points, CM positions. */
static void place(rnea* s, const double* q) {
  static const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int i = 0; i < s->n; ++i) {
    const int p = s->parent[i];
    const double* Rp = p < 0 ? I : s->R + 9 * p;
    const v3 rp = p < 0 ? (v3){{0, 0, 0}} : s->r[p];
    double Rrel[9];
    rot(at3(s->axis, i), q[i], Rrel);
    matmul(Rp, Rrel, s->R + 9 * i);
    s->z[i] = mul(Rp, at3(s->axis, i));
    s->o[i] = add(rp, mul(Rp, at3(s->a, i)));
    s->r[i] = sub(s->o[i], mul(s->R + 9 * i, at3(s->c, i)));
  }
}

/* Joint torques that give accelerations qdd at speeds u, with gravity g (RNEA). */
static void newtonEuler(rnea* s, const double* u, const double* qdd, const double* g, double* tau) {
  const v3 grav = {{g[0], g[1], g[2]}};
  for (int i = 0; i < s->n; ++i) { /* outward: velocities and accelerations */
    const int p = s->parent[i];
    const v3 zero = {{0, 0, 0}};
    const v3 wp = p < 0 ? zero : s->w[p], vp = p < 0 ? zero : s->v[p];
    const v3 alp = p < 0 ? zero : s->al[p], acp = p < 0 ? zero : s->ac[p];
    const v3 rp = p < 0 ? zero : s->r[p];
    const v3 d = sub(s->o[i], rp), b = sub(s->r[i], s->o[i]);
    s->w[i] = add(wp, scale(u[i], s->z[i]));
    s->al[i] = add(add(alp, scale(qdd[i], s->z[i])), scale(u[i], cross(wp, s->z[i])));
    const v3 ao = add(add(acp, cross(alp, d)), cross(wp, cross(wp, d))); /* joint point */
    s->v[i] = add(add(vp, cross(wp, d)), cross(s->w[i], b));
    s->ac[i] = add(add(ao, cross(s->al[i], b)), cross(s->w[i], cross(s->w[i], b)));
  }
  for (int i = 0; i < s->n; ++i) s->F[i] = s->N[i] = (v3){{0, 0, 0}};
  for (int i = s->n - 1; i >= 0; --i) { /* inward: forces and moments about joint points */
    double Jw[9], tmp[9], Rt[9];
    const double* R = s->R + 9 * i;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) Rt[3 * r + c] = R[3 * c + r];
    matmul(R, s->J + 9 * i, tmp);
    matmul(tmp, Rt, Jw);
    const v3 f = scale(s->mass[i], sub(s->ac[i], grav));
    const v3 Lw = mul(Jw, s->w[i]);
    const v3 n = add(mul(Jw, s->al[i]), cross(s->w[i], Lw));
    s->F[i] = add(s->F[i], f);
    s->N[i] = add(s->N[i], add(n, cross(sub(s->r[i], s->o[i]), f)));
    tau[i] = dot(s->z[i], s->N[i]);
    const int p = s->parent[i];
    if (p >= 0) {
      s->F[p] = add(s->F[p], s->F[i]);
      s->N[p] = add(s->N[p], add(s->N[i], cross(sub(s->o[i], s->o[p]), s->F[i])));
    }
  }
}

/* Solve M x = b in place (M symmetric positive definite, n x n, row-major); 0 if not. */
static int cholesky(int n, double* M, double* L, double* b) {
  for (int j = 0; j < n; ++j) {
    double d = M[n * j + j];
    for (int k = 0; k < j; ++k) d -= L[n * j + k] * L[n * j + k];
    if (!(d > 0)) return 0;
    L[n * j + j] = sqrt(d);
    for (int i = j + 1; i < n; ++i) {
      double s = M[n * i + j];
      for (int k = 0; k < j; ++k) s -= L[n * i + k] * L[n * j + k];
      L[n * i + j] = s / L[n * j + j];
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < i; ++k) b[i] -= L[n * i + k] * b[k];
    b[i] /= L[n * i + i];
  }
  for (int i = n - 1; i >= 0; --i) {
    for (int k = i + 1; k < n; ++k) b[i] -= L[n * k + i] * b[k];
    b[i] /= L[n * i + i];
  }
  return 1;
}

int em_plugin_abi(void) { return EM_PLUGIN_ABI; }

void em_plugin_destroy(void* self) {
  rnea* s = self;
  if (!s) return;
  void* blocks[] = {s->parent, s->mass, s->J, s->axis, s->a, s->c, s->k, s->damp, s->rest, s->R, s->z, s->o, s->r,
                    s->w, s->v, s->al, s->ac, s->F, s->N, s->M, s->bias, s->L, s->tau};
  for (size_t i = 0; i < sizeof blocks / sizeof blocks[0]; ++i) free(blocks[i]);
  free(s);
}

/* The hinges of one joint: how many, and the axis of hinge j in its parent link's frame. */
static int hinges(const em_body* b, int j, double axis[3]) {
  const int n = b->joint == EM_REVOLUTE ? 1 : b->joint == EM_UNIVERSAL ? 2 : b->joint == EM_GIMBAL ? 3 : 0;
  if (j < n) {
    if (b->joint == EM_GIMBAL) axis[0] = j == 0, axis[1] = j == 1, axis[2] = j == 2; /* Rx Ry Rz, body-fixed */
    else memcpy(axis, b->axis[j], 3 * sizeof(double));
  }
  return n;
}

void* em_plugin_create(const em_model* m, char* err, size_t err_size) {
  double axis[3];
  for (int i = 0; i < m->n_bodies; ++i)
    if (!hinges(&m->bodies[i], 0, axis)) {
      snprintf(err, err_size, "rnea example: revolute, universal and gimbal joints only (body '%s' has another kind)",
               m->bodies[i].name);
      return NULL;
    }
  const int n = m->nq; /* one link per hinge: link k is coordinate k */
  rnea* s = calloc(1, sizeof *s);
  s->n = n;
  s->parent = calloc(n, sizeof(int));
  s->mass = calloc(n, sizeof(double)), s->J = calloc(9 * n, sizeof(double)), s->axis = calloc(3 * n, sizeof(double));
  s->a = calloc(3 * n, sizeof(double)), s->c = calloc(3 * n, sizeof(double));
  s->k = calloc(n, sizeof(double)), s->damp = calloc(n, sizeof(double)), s->rest = calloc(n, sizeof(double));
  s->R = calloc(9 * n, sizeof(double));
  v3** vs[] = {&s->z, &s->o, &s->r, &s->w, &s->v, &s->al, &s->ac, &s->F, &s->N};
  for (size_t i = 0; i < sizeof vs / sizeof vs[0]; ++i) *vs[i] = calloc(n, sizeof(v3));
  s->M = calloc(n * n, sizeof(double)), s->L = calloc(n * n, sizeof(double));
  s->bias = calloc(n, sizeof(double)), s->tau = calloc(n, sizeof(double));
  memcpy(s->g, m->gravity, sizeof s->g);
  for (int i = 0; i < m->n_bodies; ++i) {
    const em_body* b = &m->bodies[i];
    const int first = b->iq, count = hinges(b, 0, axis);
    for (int j = 0; j < count; ++j) {
      const int k = first + j;
      const int last = j + 1 == count; /* the body itself; the hinges before it are massless, their CM at the joint point */
      hinges(b, j, s->axis + 3 * k);
      s->parent[k] = j > 0 ? k - 1 : b->parent < 0 ? -1 : m->bodies[b->parent].iq + m->bodies[b->parent].nq - 1;
      if (j == 0) memcpy(s->a + 3 * k, b->in_parent, 3 * sizeof(double));
      if (last) {
        s->mass[k] = b->mass;
        memcpy(s->J + 9 * k, b->inertia, 9 * sizeof(double));
        memcpy(s->c + 3 * k, b->in_body, 3 * sizeof(double));
      }
      if (b->spring_k) s->k[k] = b->spring_k[j], s->damp[k] = b->spring_c[j], s->rest[k] = b->spring_rest[j];
    }
  }
  return s;
}

int em_plugin_udot(void* self, double t, const double* q, const double* u, const double* tau, double* udot, char* err,
                   size_t err_size) {
  (void)t;
  rnea* s = self;
  const int n = s->n;
  const double nog[3] = {0, 0, 0};
  place(s, q);
  for (int i = 0; i < n; ++i) udot[i] = 0;
  newtonEuler(s, u, udot, s->g, s->bias);
  for (int k = 0; k < n; ++k) { /* column k of M: unit acceleration of joint k, at rest, no gravity */
    for (int i = 0; i < n; ++i) udot[i] = i == k;
    for (int i = 0; i < n; ++i) s->w[i] = (v3){{0, 0, 0}};
    double* zero_u = s->tau;
    for (int i = 0; i < n; ++i) zero_u[i] = 0;
    double col[n];
    newtonEuler(s, zero_u, udot, nog, col);
    for (int i = 0; i < n; ++i) s->M[n * i + k] = col[i];
  }
  for (int i = 0; i < n; ++i) udot[i] = tau[i] - s->k[i] * (q[i] - s->rest[i]) - s->damp[i] * u[i] - s->bias[i];
  if (!cholesky(n, s->M, s->L, udot)) {
    snprintf(err, err_size, "rnea example: the mass matrix is not positive definite");
    return 1;
  }
  return 0;
}
