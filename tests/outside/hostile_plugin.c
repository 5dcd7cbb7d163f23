/* hostile_plugin.c: plugins that misbehave, one way each (HOSTILE_* picks it),
 * for tests/outside/test_plugin.cpp and the CLI's hostile cases. Well-behaved
 * until they misbehave: u' = -q + tau (each coordinate a unit oscillator). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "eigenmass_plugin.h"

typedef struct { int nq, nu; } self_t;

int em_plugin_abi(void) {
#ifdef HOSTILE_ABI
  return EM_PLUGIN_ABI + 98;
#else
  return EM_PLUGIN_ABI;
#endif
}

#ifdef HOSTILE_KINDS
/* Written from the header alone: the name of every kind it names, by a switch
   with no default (a compiler warns on a kind it leaves out), "unnamed" for a
   value the header does not name. */
static const char* kind_name(int k) {
  switch ((enum em_joint_kind)k) {
    case EM_REVOLUTE: return "revolute";
    case EM_UNIVERSAL: return "universal";
    case EM_GIMBAL: return "gimbal";
    case EM_BALL: return "ball";
    case EM_PRISMATIC: return "prismatic";
    case EM_FREE: return "free";
    case EM_PLANAR: return "planar";
    case EM_JOINT_KINDS: break;
  }
  return "unnamed";
}
#endif

void* em_plugin_create(const em_model* m, char* err, size_t err_size) {
#ifdef HOSTILE_KINDS
  /* Refuses every model, naming the kinds of its joints in body order. */
  size_t at = (size_t)snprintf(err, err_size, "kinds:");
  for (int i = 0; i < m->n_bodies && at < err_size; ++i)
    at += (size_t)snprintf(err + at, err_size - at, " %s", kind_name(m->bodies[i].joint));
  return NULL;
#elif defined(HOSTILE_NULL)
  snprintf(err, err_size, "this plugin refuses\nevery \x1b[31mmodel");  /* a newline and ESC: escaped in our line */
  (void)m;
  return NULL;
#else
  (void)err, (void)err_size;
#ifdef HOSTILE_PRINT
  printf("the plugin talks on stdout");  /* no newline: left in stdio's buffer when the child ends */
#endif
  self_t* s = malloc(sizeof *s);
  s->nq = m->nq, s->nu = m->nu;
  return s;
#endif
}

#ifndef HOSTILE_NOSYM
int em_plugin_udot(void* self, double t, const double* q, const double* u, const double* tau, double* udot, char* err,
                   size_t err_size) {
  const self_t* s = self;
  (void)u, (void)err, (void)err_size;
  const double when = 0.0
#ifdef HOSTILE_LATE
                      + 0.25
#endif
      ;
  if (t >= when) {
#if defined(HOSTILE_NAN)
    udot[0] = NAN;
    return 0;
#elif defined(HOSTILE_SEGV)
    volatile int* p = NULL;
    *p = 1;
#elif defined(HOSTILE_HANG)
    for (volatile int spin = 1; spin;) {
    }
#elif defined(HOSTILE_ERROR)
    snprintf(err, err_size, "the plugin gave up at t = %g", t);
    return 7;
#elif defined(HOSTILE_TAU)
    /* Fails only where tau is not zero: on a mechanism without drives or
       point springs, in the multipliers' extra calls alone. */
    for (int i = 0; i < s->nu; ++i)
      if (tau[i] != 0) {
        snprintf(err, err_size, "no tau wanted (t = %g)", t);
        return 3;
      }
#endif
  }
  for (int i = 0; i < s->nu; ++i) udot[i] = -q[i] + tau[i];
  return 0;
}
#endif

void em_plugin_destroy(void* self) { free(self); }
