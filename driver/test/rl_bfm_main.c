/*
 * rl_bfm_main.c: the driver's bus-functional test program (docs/driver.md). The bus is a line protocol on
 * stdin/stdout, served by the Scala test (reducerload.regmap.BusFunctionalModel), which performs each request
 * as a bus transaction on the simulated RTL:
 *
 *   R <byte offset, hex>            -> the test answers one line: <value, hex>
 *   W <byte offset, hex> <value, hex>   (no answer)
 *
 * Every other line is a result "<key> <value>" the test compares with its models. The program takes its
 * inputs as arguments, each a word followed by its numbers:
 *
 *   payload M CX CY CZ IXX IXY IXZ IYY IYZ IZZ     write, commit, read back (SI)
 *   abb M X_MM Y_MM Z_MM Q1 Q2 Q3 Q4 IX IY IZ      the same from ABB-style load data
 *   refuse M CX CY CZ IXX IXY IXZ IYY IYZ IZZ      a payload the driver must refuse (prints the status)
 *   torque CODE                                    a torque code in N m
 *   snapshot                                       monitor snapshot, every figure of every joint
 *   sample Q1..Qn QD1..QDn QDD1..QDDn              register-driven sample mode
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "reducer_load.h"

static uint32_t bfm_read32(void *ctx, uint32_t offset) {
  char line[64];
  (void)ctx;
  printf("R %lx\n", (unsigned long)offset);
  fflush(stdout);
  if (fgets(line, sizeof line, stdin) == NULL) {
    fprintf(stderr, "rl_bfm_main: the bus closed during a read of 0x%lx\n", (unsigned long)offset);
    exit(3);
  }
  return (uint32_t)strtoul(line, NULL, 16);
}

static void bfm_write32(void *ctx, uint32_t offset, uint32_t value) {
  (void)ctx;
  printf("W %lx %lx\n", (unsigned long)offset, (unsigned long)value);
  fflush(stdout);
}

/* `n` numbers from argv after index *i. */
static int numbers(int argc, char **argv, int *i, int n, double *out) {
  int k;
  if (*i + n >= argc) return 0;
  for (k = 0; k < n; k++) out[k] = strtod(argv[++*i], NULL);
  return 1;
}

static void print_payload(const char *what, const rl_payload *p) {
  int k;
  printf("%s.mass %.17g\n", what, p->mass);
  for (k = 0; k < 3; k++) printf("%s.com%d %.17g\n", what, k, p->com[k]);
  for (k = 0; k < 6; k++) printf("%s.inertia%d %.17g\n", what, k, p->inertia[k]);
}

static void commit_and_read(const rl_device *dev, const char *what, rl_status written) {
  uint32_t before = 0, after = 0;
  rl_payload back;
  printf("%s.write %d\n", what, (int)written);
  printf("%s.sequence_status %d\n", what, (int)rl_payload_sequence(dev, &before));
  printf("%s.commit %d\n", what, (int)rl_payload_commit(dev));
  rl_payload_sequence(dev, &after);
  printf("%s.sequence_step %lu\n", what, (unsigned long)((after - before) & 0xffu));
  if (rl_payload_read_staged(dev, &back) == RL_OK) print_payload(what, &back);
}

int main(int argc, char **argv) {
  rl_device dev;
  rl_identity id;
  rl_status s;
  int i;
  memset(&id, 0, sizeof id);
  s = rl_init(&dev, bfm_read32, bfm_write32, NULL, &id);
  printf("init %d\n", (int)s);
  printf("id.magic %lu\nid.version %lu\nid.design_hash %lu\nid.joints %lu\nid.clocks_per_sample %lu\n",
         (unsigned long)id.magic, (unsigned long)id.version, (unsigned long)id.design_hash,
         (unsigned long)id.joints, (unsigned long)id.clocks_per_sample);
  if (s != RL_OK) return 1;
  for (i = 1; i < argc; i++) {
    double v[3 * RL_JOINTS > 11 ? 3 * RL_JOINTS : 11];
    if (strcmp(argv[i], "payload") == 0 || strcmp(argv[i], "refuse") == 0) {
      rl_payload p;
      int k, refuse = strcmp(argv[i], "refuse") == 0;
      if (!numbers(argc, argv, &i, 10, v)) return 2;
      p.mass = v[0];
      for (k = 0; k < 3; k++) p.com[k] = v[1 + k];
      for (k = 0; k < 6; k++) p.inertia[k] = v[4 + k];
      s = rl_payload_write(&dev, &p);
      if (refuse)
        printf("refuse.write %d\n", (int)s);
      else
        commit_and_read(&dev, "payload", s);
    } else if (strcmp(argv[i], "abb") == 0) {
      rl_abb_loaddata l;
      rl_payload p;
      if (!numbers(argc, argv, &i, 11, v)) return 2;
      l.mass = v[0];
      memcpy(l.cog_mm, &v[1], sizeof l.cog_mm);
      memcpy(l.aom, &v[4], sizeof l.aom);
      l.ix = v[8];
      l.iy = v[9];
      l.iz = v[10];
      if (rl_payload_from_abb(&l, &p) == RL_OK) print_payload("abb_si", &p);
      commit_and_read(&dev, "abb", rl_payload_write_abb(&dev, &l));
    } else if (strcmp(argv[i], "torque") == 0) {
      if (i + 1 >= argc) return 2;
      i++;
      printf("torque.%s %.17g\n", argv[i], rl_torque_to_si((int64_t)strtoll(argv[i], NULL, 10)));
    } else if (strcmp(argv[i], "snapshot") == 0) {
      static rl_monitor m;
      int j, b;
      s = rl_monitor_snapshot(&dev, 0, &m);
      printf("snapshot %d\n", (int)s);
      if (s != RL_OK) continue;
      printf("snapshot_count %lu\n", (unsigned long)m.snapshot_count);
      for (j = 0; j < RL_JOINTS; j++) {
        const rl_joint_figures *f = &m.joint[j];
        printf("j%d.samples %llu\n", j + 1, (unsigned long long)f->samples);
        printf("j%d.out_of_range_samples %llu\n", j + 1, (unsigned long long)f->out_of_range_samples);
        printf("j%d.peak_torque %.17g\n", j + 1, f->peak_torque);
        printf("j%d.min_torque %.17g\n", j + 1, f->min_torque);
        printf("j%d.repeated_peak_samples %llu\n", j + 1, (unsigned long long)f->repeated_peak_samples);
        printf("j%d.momentary_peak_events %llu\n", j + 1, (unsigned long long)f->momentary_peak_events);
        printf("j%d.last_event_peak_abs %.17g\n", j + 1, f->last_event_peak_abs);
        printf("j%d.last_event_duration %llu\n", j + 1, (unsigned long long)f->last_event_duration);
        printf("j%d.last_event_speed_abs %.17g\n", j + 1, f->last_event_speed_abs);
        printf("j%d.flags %lu\n", j + 1, (unsigned long)f->flags);
        printf("j%d.damage_sum %.17g\n", j + 1, f->damage_sum);
        printf("j%d.speed_sum %.17g\n", j + 1, f->speed_sum);
        for (b = 0; b < (int)f->histogram_bins; b++)
          printf("j%d.histogram_%d %llu\n", j + 1, b, (unsigned long long)f->histogram[b]);
      }
    } else if (strcmp(argv[i], "sample") == 0) {
      double tau[RL_JOINTS];
      uint32_t flags = 0;
      int j;
      if (!numbers(argc, argv, &i, 3 * RL_JOINTS, v)) return 2;
      s = rl_sample(&dev, &v[0], &v[RL_JOINTS], &v[2 * RL_JOINTS], tau, &flags);
      printf("sample %d\n", (int)s);
      if (s != RL_OK) continue;
      for (j = 0; j < RL_JOINTS; j++) printf("sample.tau%d %.17g\n", j + 1, tau[j]);
      printf("sample.out_of_range %lu\n", (unsigned long)flags);
    } else {
      fprintf(stderr, "rl_bfm_main: unknown argument '%s'\n", argv[i]);
      return 2;
    }
  }
  printf("done\n");
  return 0;
}
