/* A tracer that breaks the tracer ABI in one way, chosen when it is built (FAULT, below), and otherwise answers
 * every ray with a plausible hit: object 0 at t = 1, or every ray's two hits at t = 1 and 2. The tests hold each
 * fault to the verdict twinray gives it (tests/plugin_test.cpp; the last three, which no process survives, through
 * `twinray conform`); FAULT_NONE is the control that must pass. */
#include <twinray/tracer.h>

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>

#define FAULT_NONE 0
#define FAULT_NO_ENTRY 1
#define FAULT_OTHER_VERSION 2
#define FAULT_BUILD_FAILS 3
#define FAULT_NAN_T 4
#define FAULT_NEGATIVE_T 5
#define FAULT_T_BEYOND_RANGE 6
#define FAULT_WRONG_COUNT 7
#define FAULT_UNKNOWN_OBJECT 8
#define FAULT_HITS_OUT_OF_ORDER 9
#define FAULT_CALL_FAILS 10
#define FAULT_CRASHES 11
#define FAULT_HANGS 12
#define FAULT_EXITS 13

static int built_scene;

static void* build(const twinray_scene* scene, char* error, size_t error_size) {
    (void)scene;
    if (FAULT == FAULT_BUILD_FAILS) {
        snprintf(error, error_size, "no room for the scene");
        return NULL;
    }
    return &built_scene;
}

static void answer(twinray_hit* hit, double t) {
    hit->hit = 1;
    hit->object = FAULT == FAULT_UNKNOWN_OBJECT ? 1000 : 0;
    hit->primitive = TWINRAY_NONE;
    hit->instance = TWINRAY_NONE;
    hit->t = FAULT == FAULT_NAN_T ? NAN : FAULT == FAULT_NEGATIVE_T ? -t : FAULT == FAULT_T_BEYOND_RANGE ? 1e300 : t;
    hit->normal[0] = 0;
    hit->normal[1] = 0;
    hit->normal[2] = 1;
    hit->u = 0;
    hit->v = 0;
    hit->entering = 1;
}

static int intersect(void* built, const twinray_ray* rays, size_t count, twinray_hit* hits, size_t* written,
                     char* error, size_t error_size) {
    size_t i;
    (void)built;
    (void)rays;
    if (FAULT == FAULT_CALL_FAILS) {
        snprintf(error, error_size, "the device was lost");
        return 3;
    }
    if (FAULT == FAULT_CRASHES) {
        raise(SIGSEGV);
    }
    if (FAULT == FAULT_HANGS) {
        volatile int forever = 1;
        while (forever) {
        }
    }
    if (FAULT == FAULT_EXITS) {
        exit(3);
    }
    for (i = 0; i < count; ++i) {
        answer(&hits[i], 1);
    }
    *written = FAULT == FAULT_WRONG_COUNT ? count - 1 : count;
    return 0;
}

static int hits_along(void* built, const twinray_ray* ray, twinray_hit* hits, size_t capacity, size_t* total,
                      char* error, size_t error_size) {
    (void)built;
    (void)ray;
    (void)error;
    (void)error_size;
    if (capacity >= 2) {
        answer(&hits[0], FAULT == FAULT_HITS_OUT_OF_ORDER ? 2 : 1);
        answer(&hits[1], FAULT == FAULT_HITS_OUT_OF_ORDER ? 1 : 2);
    }
    *total = 2;
    return 0;
}

static void release(void* built) { (void)built; }

static const twinray_tracer tracer = {FAULT == FAULT_OTHER_VERSION ? 2u : TWINRAY_TRACER_ABI_VERSION,
                                      0,
                                      "faulty",
                                      "1",
                                      TWINRAY_KIND_SPHERE,
                                      0x1p-24,
                                      build,
                                      intersect,
                                      hits_along,
                                      release};

#if FAULT != FAULT_NO_ENTRY
const twinray_tracer* twinray_tracer_entry(void) { return &tracer; }
#else
const twinray_tracer* another_entry(void) { return &tracer; }
#endif
