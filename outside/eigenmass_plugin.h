/* eigenmass_plugin.h: the C ABI of a method from outside (docs/plugins.md).
 *
 * A plugin is a shared library that computes u' = A^-1 B for a model that
 * eigenmass hands it; eigenmass integrates it with its own integrators and
 * judges it like every built-in method (eigenmass compare --plugin
 * NAME=path/libx.so). It exports four symbols with C linkage:
 *
 *   int   em_plugin_abi(void);                       returns EM_PLUGIN_ABI
 *   void* em_plugin_create(const em_model*, char* err, size_t err_size);
 *   int   em_plugin_udot(void*, double t, const double* q, const double* u,
 *                        const double* tau, double* udot, char* err, size_t err_size);
 *   void  em_plugin_destroy(void*);
 *
 * create returns the plugin's own state for one model, or NULL with a one-line
 * message in err (at most err_size bytes, NUL-terminated). It is never called
 * in eigenmass's own process: every call of create, udot and destroy happens
 * in a child process (fork) that eigenmass watches, so a crash or a hang ends
 * one run. create is called once per child: once for the probe at the initial
 * state (before any run), once per run, and once per crosscheck of the plugin;
 * each child's destroy ends its state. Nothing a plugin keeps in globals
 * carries from one run to the next. udot writes u' = A^-1 (B + tau) (nu
 * numbers) at (t, q, u) and returns 0, or returns nonzero with a message in
 * err: the run then fails at t with that cause. Everything eigenmass passes is
 * valid only during the call; copy what you keep.
 *
 * tau (nu numbers, never NULL) is a generalized force added to the tree's
 * right-hand side B (gravity, the joints' springs and dampers, the velocity
 * terms). On a tree it is zero. On a mechanism (a scene with loops, point
 * spring-dampers or joint drives: em_model's n_loops, n_point_springs,
 * n_drives) the plugin still computes the tree's u' and nothing else:
 * eigenmass puts the drives' torques and the point springs' J^T f into tau,
 * and closes the loops around the plugin (docs/theory.md eq. (M7)), taking
 * A^-1 G^T from the plugin's own u' by its linearity in tau: one more call
 * per closure row, at the same (t, q, u), with tau plus a scaled row of G.
 * So u' must be linear in tau (it is, for any u' = A^-1 (B + tau)), and a
 * plugin that ignores tau is wrong on every mechanism (a test catches it).
 *
 * Sizes and orders: bodies come parents first (parent < index), and q, u and
 * u' are in that order, each body's joint coordinates at q[iq .. iq+nq) and
 * speeds at u[iu .. iu+nu). Units are SI; vectors and matrices are in the
 * frames named below. The joint kinds and their coordinates (docs/theory.md
 * §1 and §12):
 *
 *   kind        nq nu  q                                   u
 *   revolute     1  1  angle about axis[0]                  q'
 *   universal    2  2  angles about axis[0], then axis[1]   q'
 *   gimbal       3  3  x-y-z body-fixed Cardan angles       q'
 *   ball         4  3  unit quaternion [w,x,y,z]            angular velocity, parent frame
 *   prismatic    1  1  slide along axis[0]                  q'
 *   free         7  6  [x, y, z, quaternion w,x,y,z]        [x', y', z', angular velocity, parent frame]
 *   planar       3  3  [s1, s2, theta]: slides along        q'
 *                      axis[0], axis[1], then the turn
 *                      about n = axis[0] x axis[1]
 *
 * The rotation of a body relative to its parent is Rot(axis0, q0) (revolute),
 * Rot(a0,q0) Rot(a1,q1) (universal), Rx Ry Rz (gimbal), R(quaternion) (ball,
 * free), Rot(n, theta) (planar); a slide moves the joint point by x along
 * axis[0] (prismatic), by (x, y, z) along the parent's axes (free) or by
 * s1 axis[0] + s2 axis[1] (planar), before the rotation. These are every kind
 * there is: a kind eigenmass adds gets its value here and a new
 * EM_PLUGIN_ABI, so a plugin never receives a kind its header does not name.
 *
 * The ABI changes only with EM_PLUGIN_ABI; a library built against another
 * version is refused in one line before any run.
 */
#ifndef EIGENMASS_PLUGIN_H
#define EIGENMASS_PLUGIN_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* 3: em_joint_kind names EM_PLANAR (6), which ABI 2 passed unnamed.
   2: em_plugin_udot takes tau; em_model counts the mechanism's loops, point
   springs and drives. 1: a tree's u' only. Every other value is refused. */
#define EM_PLUGIN_ABI 3

/* Joint kinds (the values are eigenmass's JointType order, checked when
   eigenmass is compiled); EM_JOINT_KINDS counts them. */
enum em_joint_kind {
  EM_REVOLUTE = 0,
  EM_UNIVERSAL = 1,
  EM_GIMBAL = 2,
  EM_BALL = 3,
  EM_PRISMATIC = 4,
  EM_FREE = 5,
  EM_PLANAR = 6,
  EM_JOINT_KINDS = 7
};

/* One body and its inboard joint. */
typedef struct em_body {
  const char* name;
  int parent;            /* index of the parent in em_model.bodies, -1: the ground */
  int joint;             /* enum em_joint_kind */
  int iq, nq, iu, nu;    /* where its joint's coordinates and speeds sit in q and u */
  double mass;           /* kg */
  double inertia[9];     /* about the CM, body frame, row-major, kg m^2 */
  /* Unit joint axes. revolute, prismatic: axis[0], in the parent frame. universal:
     axis[0] fixed in the parent, axis[1] fixed in the body (R = Rot(a0,q0) Rot(a1,q1):
     axis[1]'s components are the same in the body frame at every q, and in the
     parent frame at q = 0). planar: axis[0] and axis[1], perpendicular, both in
     the parent frame. gimbal, ball, free: unused, all zero (the kinds' own axes
     are the parent's x, y, z). */
  double axis[2][3];
  double in_parent[3];   /* a: parent CM to the joint point, parent frame (world for a root), m */
  double in_body[3];     /* c: body CM to the joint point, body frame, m */
  /* A linear spring-damper per joint speed, generalized force -k (q - rest) - c u;
     NULL when the joint has none (nu numbers each). */
  const double* spring_k;
  const double* spring_c;
  const double* spring_rest;
} em_body;

/* The model a plugin is created for. */
typedef struct em_model {
  int abi;                /* EM_PLUGIN_ABI of the harness */
  const char* name;       /* the scene's name */
  int n_bodies, nq, nu;
  double gravity[3];      /* world frame, m/s^2 */
  const em_body* bodies;  /* n_bodies, parents first */
  const char* scene_json; /* the tree as an eigenmass-scene/1 file, bodies in this order (docs/scene-format.md); no loops, point springs or drives in it */
  /* What makes the scene a mechanism, for the plugin's information only: its
     closures, point spring-dampers and driven joints. eigenmass handles all
     three (through tau and its own constraint formulation); 0 on a tree. */
  int n_loops, n_point_springs, n_drives;
} em_model;

int em_plugin_abi(void);
void* em_plugin_create(const em_model* model, char* err, size_t err_size);
int em_plugin_udot(void* self, double t, const double* q, const double* u, const double* tau, double* udot, char* err,
                   size_t err_size);
void em_plugin_destroy(void* self);

#ifdef __cplusplus
}
#endif

#endif /* EIGENMASS_PLUGIN_H */
