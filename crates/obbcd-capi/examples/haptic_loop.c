/* A haptic loop over obbcd's C ABI: a tissue patch kept resident (group 0), a tilted
 * instrument of four boxes (group 1, a rigid body: its boxes set once in its own frame, a pose
 * each frame) that goes down onto the tissue, slides along it into a second instrument
 * (group 2) and rises again, turning a little about the vertical, one detection per 1 kHz
 * frame, the tissue moving every 25th frame. Prints a line per frame; with --trace, also every
 * box and pose it sets and every pair with its contact (the tests compare them with a
 * reference).
 *
 * Build (from the workspace, after `cargo build --release -p obbcd-capi`):
 *   cc -std=c11 -O2 -I crates/obbcd-capi/include crates/obbcd-capi/examples/haptic_loop.c \
 *      target/release/libobbcd_c.a -lpthread -ldl -lm -o haptic_loop
 */
#include "obbcd.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

enum { SIDE = 48, TISSUE = SIDE * SIDE, TOOL = 4, FRAMES = 200, TISSUE_EVERY = 25 };

static int trace;

/* Prints a failed call's reason and returns 1. */
static int failed(const char *what, ObbcdStatus status) {
  fprintf(stderr, "%s failed (status %d): %s\n", what, (int)status, obbcd_last_error());
  return 1;
}

static void print_box(uint32_t group, size_t i, const ObbcdBox *b) {
  if (!trace) return;
  printf("box %u %zu", group, i);
  for (int k = 0; k < 3; k++) printf(" %.17g", b->center[k]);
  for (int r = 0; r < 3; r++)
    for (int k = 0; k < 3; k++) printf(" %.17g", b->axes[r][k]);
  for (int k = 0; k < 3; k++) printf(" %.17g", b->half[k]);
  printf("\n");
}

/* Sets a group's boxes (and traces them). */
static ObbcdStatus set(ObbcdEngine *e, uint32_t group, const ObbcdBox *boxes, size_t n) {
  for (size_t i = 0; i < n; i++) print_box(group, i, &boxes[i]);
  return obbcd_set_boxes(e, group, boxes, n);
}

/* 1 mm plates, 0.25 mm thick, on a surface that breathes with time t (ms). */
static void tissue(ObbcdBox *out, double t) {
  for (int i = 0; i < SIDE; i++)
    for (int j = 0; j < SIDE; j++) {
      ObbcdBox *b = &out[i * SIDE + j];
      memset(b, 0, sizeof *b);
      b->center[0] = i + 0.5;
      b->center[1] = j + 0.5;
      b->center[2] = 0.3 * sin(0.2 * i + 0.001 * t) * cos(0.15 * j);
      b->axes[0][0] = b->axes[1][1] = b->axes[2][2] = 1.0;
      b->half[0] = b->half[1] = 0.5;
      b->half[2] = 0.125;
    }
}

/* The instrument in its own frame: four 2 mm boxes along a shaft tilted 30 degrees, tip
 * first, the tip at the origin. */
static void instrument(ObbcdBox *out) {
  const double pi = 3.14159265358979323846, c = cos(pi / 6), s = sin(pi / 6);
  for (int n = 0; n < TOOL; n++) {
    ObbcdBox *b = &out[n];
    memset(b, 0, sizeof *b);
    double along = 1.0 + 2.0 * n; /* from the tip to this box's center */
    b->center[0] = -c * along;
    b->center[1] = 0.0;
    b->center[2] = s * along;
    b->axes[0][0] = c, b->axes[0][2] = s;
    b->axes[1][1] = 1.0;
    b->axes[2][0] = -s, b->axes[2][2] = c;
    b->half[0] = 1.0;
    b->half[1] = b->half[2] = 0.3;
  }
}

/* The instrument's pose at frame k: its tip down, along, up; turned about z by a few degrees. */
static ObbcdPose instrument_pose(int k) {
  double x = 10.0, z = 3.0;
  if (k < 50) {
    z = 3.0 - 3.0 * k / 50.0;
  } else if (k < 150) {
    z = 0.0;
    x = 10.0 + 20.0 * (k - 50) / 100.0;
  } else {
    z = 3.0 * (k - 150) / 50.0;
    x = 30.0;
  }
  double yaw = 0.1 * sin(0.05 * k), c = cos(yaw), s = sin(yaw);
  ObbcdPose p = {{{c, -s, 0.0}, {s, c, 0.0}, {0.0, 0.0, 1.0}}, {x, 24.0, z}};
  return p;
}

/* Sets a group's pose (and traces it). */
static ObbcdStatus pose(ObbcdEngine *e, uint32_t group, const ObbcdPose *p) {
  if (trace) {
    printf("pose %u", group);
    for (int r = 0; r < 3; r++)
      for (int k = 0; k < 3; k++) printf(" %.17g", p->rotation[r][k]);
    for (int k = 0; k < 3; k++) printf(" %.17g", p->translation[k]);
    printf("\n");
  }
  return obbcd_set_pose(e, group, p);
}

int main(int argc, char **argv) {
  trace = argc > 1 && strcmp(argv[1], "--trace") == 0;
  static ObbcdBox boxes[TISSUE];
  ObbcdEngine *engine = NULL;
  const uint32_t statics[] = {0};
  ObbcdStatus st = obbcd_engine_new("cross", statics, 1, 1, &engine);
  if (st != OBBCD_STATUS_OK) return failed("obbcd_engine_new", st);

  /* A bad box is refused with a reason, and changes nothing. */
  ObbcdBox tool[TOOL];
  instrument(tool);
  ObbcdBox bad = tool[0];
  bad.half[1] = NAN;
  st = obbcd_set_boxes(engine, 1, &bad, 1);
  printf("refused: status %d: %s\n", (int)st, obbcd_last_error());

  /* The instrument's boxes once, in its own frame; then a pose a frame. A rotation that is
   * not one is refused. */
  if ((st = set(engine, 1, tool, TOOL)) != OBBCD_STATUS_OK) return failed("set instrument", st);
  ObbcdPose skew = {{{1.0, 0.1, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}}, {0.0, 0.0, 0.0}};
  st = obbcd_set_pose(engine, 1, &skew);
  printf("refused: status %d: %s\n", (int)st, obbcd_last_error());

  /* The second instrument: one box standing where the first one's slide ends. */
  ObbcdBox other;
  memset(&other, 0, sizeof other);
  other.center[0] = 30.5, other.center[1] = 24.0, other.center[2] = 1.5;
  other.axes[0][0] = other.axes[1][1] = other.axes[2][2] = 1.0;
  other.half[0] = 0.5, other.half[1] = 0.5, other.half[2] = 1.0;
  if ((st = set(engine, 2, &other, 1)) != OBBCD_STATUS_OK) return failed("set group 2", st);

  size_t total = 0, most = 0;
  for (int k = 0; k < FRAMES; k++) {
    if (k % TISSUE_EVERY == 0) {
      tissue(boxes, k);
      if ((st = set(engine, 0, boxes, TISSUE)) != OBBCD_STATUS_OK) return failed("set tissue", st);
    }
    ObbcdPose p = instrument_pose(k);
    if ((st = pose(engine, 1, &p)) != OBBCD_STATUS_OK) return failed("pose instrument", st);

    size_t n = 0;
    if ((st = obbcd_detect(engine, &n)) != OBBCD_STATUS_OK) return failed("obbcd_detect", st);
    const ObbcdPair *pairs;
    const ObbcdContact *contacts;
    size_t np, nc;
    if ((st = obbcd_pairs(engine, &pairs, &np)) != OBBCD_STATUS_OK) return failed("obbcd_pairs", st);
    if ((st = obbcd_contacts(engine, &contacts, &nc)) != OBBCD_STATUS_OK)
      return failed("obbcd_contacts", st);
    if (np != n || nc != n) {
      fprintf(stderr, "frame %d: %zu pairs, %zu listed, %zu contacts\n", k, n, np, nc);
      return 1;
    }
    double deepest = 0.0;
    for (size_t p = 0; p < n; p++) {
      if (contacts[p].depth > deepest) deepest = contacts[p].depth;
      if (trace)
        printf("pair %u %u %u %u %.17g %.17g %.17g %.17g\n", pairs[p].group_a, pairs[p].index_a,
               pairs[p].group_b, pairs[p].index_b, contacts[p].normal[0], contacts[p].normal[1],
               contacts[p].normal[2], contacts[p].depth);
    }
    printf("frame %d pairs %zu deepest %.3f\n", k, n, deepest);
    total += n;
    if (n > most) most = n;
  }
  obbcd_engine_free(engine);
  printf("frames=%d pairs_total=%zu pairs_max=%zu\n", FRAMES, total, most);
  return 0;
}
