/*
 * reducer_load.c: C99 driver of the reducer-load core (docs/driver.md). No OS, no heap, no libm: every
 * design fact comes from reducer_load_regs.h and reducer_load_layout.h.
 */
#include "reducer_load.h"

#include <stddef.h>

#define RL_TWO_PI (2.0 * 3.141592653589793)

/* ---- small helpers ---- */

static uint32_t rd(const rl_device *dev, uint32_t offset) { return dev->read32(dev->ctx, offset); }
static void wr(const rl_device *dev, uint32_t offset, uint32_t value) { dev->write32(dev->ctx, offset, value); }

static int finite(double x) { return x == x && x - x == 0.0; }

/* floor() for |x| < 2^62, without libm. */
static double floor62(double x) {
  double t = (double)(int64_t)x;
  return t > x ? t - 1.0 : t;
}

/* 2^n for small n, exact. */
static double pow2(int n) {
  double r = 1.0;
  for (; n > 0; n--) r *= 2.0;
  for (; n < 0; n++) r *= 0.5;
  return r;
}

/* Round half up of x x 2^frac_bits into a signed code of `width` bits; RL_ERR_RANGE beyond it, never a wrap. */
static rl_status to_code(double x, int frac_bits, int width, int64_t *code) {
  double scaled, limit;
  if (!finite(x)) return RL_ERR_NOT_FINITE;
  scaled = x * pow2(frac_bits);
  limit = pow2(width - 1);
  if (!(scaled >= -limit - 0.5 && scaled < limit - 0.5)) return RL_ERR_RANGE;
  *code = (int64_t)floor62(scaled + 0.5);
  return RL_OK;
}

/* A field value sign-extended from its width. */
static int64_t sign_extend(uint64_t raw, unsigned width) {
  uint64_t sign = (uint64_t)1 << (width - 1);
  uint64_t mask = width >= 64 ? ~(uint64_t)0 : (((uint64_t)1 << width) - 1);
  raw &= mask;
  return (int64_t)((raw ^ sign) - sign);
}

const char *rl_status_text(rl_status s) {
  switch (s) {
    case RL_OK: return "ok";
    case RL_ERR_ARG: return "bad argument";
    case RL_ERR_MAGIC: return "no reducer-load core (magic)";
    case RL_ERR_VERSION: return "generator version differs from the headers'";
    case RL_ERR_DESIGN: return "design hash differs from the headers'";
    case RL_ERR_SHAPE: return "joint count or port format differs from the headers'";
    case RL_ERR_RANGE: return "value beyond its declared range";
    case RL_ERR_NOT_FINITE: return "value not finite";
    case RL_ERR_TIMEOUT: return "timeout";
    case RL_ERR_UNSUPPORTED: return "the design has no such block";
  }
  return "unknown status";
}

/* ---- identification ---- */

rl_status rl_init(rl_device *dev, rl_read32_fn read32, rl_write32_fn write32, void *ctx, rl_identity *id) {
  rl_identity got;
  uint32_t shape;
  if (dev == NULL || read32 == NULL || write32 == NULL) return RL_ERR_ARG;
  dev->read32 = read32;
  dev->write32 = write32;
  dev->ctx = ctx;
  dev->poll_limit = RL_DEFAULT_POLL_LIMIT;
  got.magic = rd(dev, RL_ID_MAGIC_OFFSET);
  got.version = rd(dev, RL_ID_VERSION_OFFSET);
  got.design_hash = rd(dev, RL_ID_DESIGN_HASH_OFFSET);
  shape = rd(dev, RL_ID_SHAPE_OFFSET);
  got.joints = (shape & RL_ID_SHAPE_JOINTS_MASK) >> RL_ID_SHAPE_JOINTS_SHIFT;
  got.clocks_per_sample = (shape & RL_ID_SHAPE_CLOCKS_PER_SAMPLE_MASK) >> RL_ID_SHAPE_CLOCKS_PER_SAMPLE_SHIFT;
  if (id != NULL) *id = got;
  if (got.magic != RL_ID_MAGIC_RESET) return RL_ERR_MAGIC;
  if (got.version != RL_ID_VERSION_RESET) return RL_ERR_VERSION;
  if (got.design_hash != RL_ID_DESIGN_HASH_RESET) return RL_ERR_DESIGN;
  if (got.joints != (uint32_t)RL_JOINTS) return RL_ERR_SHAPE;
  /* The port formats, as the headers' constants (the whole register: width, integer, fraction bits, sign). */
  if (rd(dev, RL_ID_Q_FORMAT_OFFSET) != RL_ID_Q_FORMAT_RESET ||
      rd(dev, RL_ID_QD_FORMAT_OFFSET) != RL_ID_QD_FORMAT_RESET ||
      rd(dev, RL_ID_QDD_FORMAT_OFFSET) != RL_ID_QDD_FORMAT_RESET ||
      rd(dev, RL_ID_TAU_FORMAT_OFFSET) != RL_ID_TAU_FORMAT_RESET)
    return RL_ERR_SHAPE;
#ifdef RL_ID_PARAMETER_FORMAT_OFFSET
  if (rd(dev, RL_ID_PARAMETER_FORMAT_OFFSET) != RL_ID_PARAMETER_FORMAT_RESET) return RL_ERR_SHAPE;
#endif
  return RL_OK;
}

/* ---- conversions ---- */

double rl_torque_to_si(int64_t code) {
  return (double)sign_extend((uint64_t)code, RL_PORT_TAU_WIDTH) * RL_PORT_TAU_SCALE;
}

rl_status rl_si_to_angle(double rad, uint32_t *code) {
  double turns, frac, scaled;
  if (code == NULL) return RL_ERR_ARG;
  if (!finite(rad)) return RL_ERR_NOT_FINITE;
  turns = rad / RL_TWO_PI;
  if (!(turns > -4.0e18 && turns < 4.0e18)) return RL_ERR_RANGE;
  frac = turns - floor62(turns);
  scaled = floor62(frac * pow2(RL_PORT_Q_FRAC_BITS) + 0.5);
  *code = (uint32_t)((uint64_t)scaled & (((uint64_t)1 << RL_PORT_Q_WIDTH) - 1));
  return RL_OK;
}

/* A port code that fits 32 bits (the qd and qdd ports). */
static rl_status to_code32(double x, int frac_bits, int width, int32_t *code) {
  int64_t c = 0;
  rl_status s;
  if (code == NULL) return RL_ERR_ARG;
  s = to_code(x, frac_bits, width, &c);
  if (s == RL_OK) *code = (int32_t)c;
  return s;
}

rl_status rl_si_to_velocity(double rad_s, int32_t *code) {
  return to_code32(rad_s, RL_PORT_QD_FRAC_BITS, RL_PORT_QD_WIDTH, code);
}

rl_status rl_si_to_acceleration(double rad_s2, int32_t *code) {
  return to_code32(rad_s2, RL_PORT_QDD_FRAC_BITS, RL_PORT_QDD_WIDTH, code);
}

/* ---- ABB load data -> payload: I = R diag(ix, iy, iz) R^T, R the rotation of the unit quaternion aom ---- */

rl_status rl_payload_from_abb(const rl_abb_loaddata *l, rl_payload *p) {
  double w, x, y, z, n2, r[3][3], d[3];
  int i, k;
  if (l == NULL || p == NULL) return RL_ERR_ARG;
  if (!finite(l->mass) || !finite(l->ix) || !finite(l->iy) || !finite(l->iz)) return RL_ERR_NOT_FINITE;
  for (i = 0; i < 3; i++)
    if (!finite(l->cog_mm[i])) return RL_ERR_NOT_FINITE;
  for (i = 0; i < 4; i++)
    if (!finite(l->aom[i])) return RL_ERR_NOT_FINITE;
  if (l->mass < 0.0 || l->ix < 0.0 || l->iy < 0.0 || l->iz < 0.0) return RL_ERR_RANGE;
  w = l->aom[0];
  x = l->aom[1];
  y = l->aom[2];
  z = l->aom[3];
  n2 = w * w + x * x + y * y + z * z;
  /* RAPID requires a normalised orientation; a quaternion off by more than rounding is a caller's error. */
  if (!(n2 > 1.0 - 1e-6 && n2 < 1.0 + 1e-6)) return RL_ERR_ARG;
  r[0][0] = 1.0 - 2.0 * (y * y + z * z) / n2;
  r[0][1] = 2.0 * (x * y - w * z) / n2;
  r[0][2] = 2.0 * (x * z + w * y) / n2;
  r[1][0] = 2.0 * (x * y + w * z) / n2;
  r[1][1] = 1.0 - 2.0 * (x * x + z * z) / n2;
  r[1][2] = 2.0 * (y * z - w * x) / n2;
  r[2][0] = 2.0 * (x * z - w * y) / n2;
  r[2][1] = 2.0 * (y * z + w * x) / n2;
  r[2][2] = 1.0 - 2.0 * (x * x + y * y) / n2;
  d[0] = l->ix;
  d[1] = l->iy;
  d[2] = l->iz;
  p->mass = l->mass;
  for (i = 0; i < 3; i++) p->com[i] = l->cog_mm[i] * 1e-3;
  {
    static const int row[6] = {0, 0, 0, 1, 1, 2}, col[6] = {0, 1, 2, 1, 2, 2};
    for (i = 0; i < 6; i++) {
      double s = 0.0;
      for (k = 0; k < 3; k++) s += r[row[i]][k] * d[k] * r[col[i]][k];
      p->inertia[i] = s;
    }
  }
  return RL_OK;
}

/* ---- payload and gravity registers ---- */

#if RL_LAYOUT_PARAMETERS > 0
typedef struct {
  uint32_t offset; /* word 0; a code wider than 32 bits takes the next words, least significant first */
  int words;
  int frac_bits;
  int width;
  int64_t lo, hi; /* the declared interval in codes: the hardware clamps beyond it */
} rl_parameter_layout;
static const rl_parameter_layout rl_parameters[RL_LAYOUT_PARAMETERS] = RL_LAYOUT_PARAMETER_TABLE;

static rl_status parameter_code(int index, double value, int64_t *code) {
  const rl_parameter_layout *pl = &rl_parameters[index];
  rl_status s = to_code(value, pl->frac_bits, pl->width, code);
  if (s != RL_OK) return s;
  return *code < pl->lo || *code > pl->hi ? RL_ERR_RANGE : RL_OK;
}

/* A code into its words: each 32 bits, the top one sign-extended (a one-word code is masked to its width). */
static void parameter_write(const rl_device *dev, int index, int64_t code) {
  const rl_parameter_layout *pl = &rl_parameters[index];
  uint64_t raw = (uint64_t)code;
  int w;
  if (pl->words == 1) {
    wr(dev, pl->offset, (uint32_t)(raw & (pl->width >= 32 ? 0xffffffffu : (((uint64_t)1 << pl->width) - 1))));
    return;
  }
  for (w = 0; w < pl->words; w++) wr(dev, pl->offset + 4u * (uint32_t)w, (uint32_t)(w < 2 ? raw >> (32 * w) : 0u));
}

/* Check every value before writing any: a refused set leaves the staged one whole. */
static rl_status parameters_write(const rl_device *dev, const int *index, const double *v, int n) {
  int64_t raw[10];
  int i;
  rl_status s;
  for (i = 0; i < n; i++)
    if ((s = parameter_code(index[i], v[i], &raw[i])) != RL_OK) return s;
  for (i = 0; i < n; i++) parameter_write(dev, index[i], raw[i]);
  return RL_OK;
}

static double parameter_value(const rl_device *dev, int index) {
  const rl_parameter_layout *pl = &rl_parameters[index];
  uint64_t raw = rd(dev, pl->offset);
  if (pl->words > 1) raw |= (uint64_t)rd(dev, pl->offset + 4u) << 32;
  return (double)sign_extend(raw, (unsigned)(pl->words > 1 ? 64 : pl->width)) * pow2(-pl->frac_bits);
}
#endif

rl_status rl_payload_write(const rl_device *dev, const rl_payload *p) {
#if RL_LAYOUT_PARAMETERS > 0 && RL_PARAM_MASS >= 0
  static const int index[10] = {RL_PARAM_MASS, RL_PARAM_CX,  RL_PARAM_CY,  RL_PARAM_CZ,  RL_PARAM_IXX,
                                RL_PARAM_IXY,  RL_PARAM_IXZ, RL_PARAM_IYY, RL_PARAM_IYZ, RL_PARAM_IZZ};
  double v[10];
  int i;
  if (dev == NULL || p == NULL) return RL_ERR_ARG;
  v[0] = p->mass;
  for (i = 0; i < 3; i++) v[1 + i] = p->com[i];
  for (i = 0; i < 6; i++) v[4 + i] = p->inertia[i];
  return parameters_write(dev, index, v, 10);
#else
  (void)dev;
  (void)p;
  return RL_ERR_UNSUPPORTED;
#endif
}

rl_status rl_payload_write_abb(const rl_device *dev, const rl_abb_loaddata *l) {
  rl_payload p;
  rl_status s = rl_payload_from_abb(l, &p);
  return s != RL_OK ? s : rl_payload_write(dev, &p);
}

rl_status rl_payload_read_staged(const rl_device *dev, rl_payload *p) {
#if RL_LAYOUT_PARAMETERS > 0 && RL_PARAM_MASS >= 0
  int i;
  if (dev == NULL || p == NULL) return RL_ERR_ARG;
  p->mass = parameter_value(dev, RL_PARAM_MASS);
  p->com[0] = parameter_value(dev, RL_PARAM_CX);
  p->com[1] = parameter_value(dev, RL_PARAM_CY);
  p->com[2] = parameter_value(dev, RL_PARAM_CZ);
  {
    static const int index[6] = {RL_PARAM_IXX, RL_PARAM_IXY, RL_PARAM_IXZ, RL_PARAM_IYY, RL_PARAM_IYZ, RL_PARAM_IZZ};
    for (i = 0; i < 6; i++) p->inertia[i] = parameter_value(dev, index[i]);
  }
  return RL_OK;
#else
  (void)dev;
  (void)p;
  return RL_ERR_UNSUPPORTED;
#endif
}

rl_status rl_gravity_write(const rl_device *dev, const double g[3]) {
#if RL_LAYOUT_PARAMETERS > 0 && RL_PARAM_GX >= 0
  static const int index[3] = {RL_PARAM_GX, RL_PARAM_GY, RL_PARAM_GZ};
  if (dev == NULL || g == NULL) return RL_ERR_ARG;
  return parameters_write(dev, index, g, 3);
#else
  (void)dev;
  (void)g;
  return RL_ERR_UNSUPPORTED;
#endif
}

rl_status rl_payload_commit(const rl_device *dev) {
#if RL_LAYOUT_PARAMETERS > 0
  if (dev == NULL) return RL_ERR_ARG;
  wr(dev, RL_PAYLOAD_COMMIT_OFFSET, RL_PAYLOAD_COMMIT_COMMIT_MASK);
  return RL_OK;
#else
  (void)dev;
  return RL_ERR_UNSUPPORTED;
#endif
}

rl_status rl_payload_sequence(const rl_device *dev, uint32_t *sequence) {
#if RL_LAYOUT_PARAMETERS > 0
  if (dev == NULL || sequence == NULL) return RL_ERR_ARG;
  *sequence = (rd(dev, RL_PAYLOAD_SEQUENCE_OFFSET) & RL_PAYLOAD_SEQUENCE_VALUE_MASK) >> RL_PAYLOAD_SEQUENCE_VALUE_SHIFT;
  return RL_OK;
#else
  (void)dev;
  (void)sequence;
  return RL_ERR_UNSUPPORTED;
#endif
}

/* ---- monitor ---- */

#if RL_LAYOUT_HAS_MONITOR
typedef struct {
  uint32_t offset;
  unsigned words;
  unsigned is_signed;
  double scale;
} rl_figure_layout;
static const rl_figure_layout rl_figures[RL_JOINTS][RL_FIGURES_PER_JOINT] = RL_LAYOUT_MONITOR_FIGURES;
static const unsigned rl_joint_bins[RL_JOINTS] = RL_LAYOUT_JOINT_BINS;

/* A figure's value as a double (counts up to 2^53 exactly; the damage sum's 100+ bits approximately). */
static double figure_value(const rl_device *dev, const rl_figure_layout *f) {
  double v = 0.0, weight = 1.0;
  unsigned w;
  for (w = 0; w < f->words; w++) {
    uint32_t word = rd(dev, f->offset + 4u * w);
    if (f->is_signed && w == f->words - 1)
      v += (double)(int32_t)word * weight; /* the top word carries the sign (sign-extended to whole words) */
    else
      v += (double)word * weight;
    weight *= 4294967296.0;
  }
  return f->scale != 0.0 ? v * f->scale : v;
}

/* A count (unsigned, at most 64 bits: the 20-year counters are 40 to 44). */
static uint64_t figure_count(const rl_device *dev, const rl_figure_layout *f) {
  uint64_t v = rd(dev, f->offset);
  if (f->words > 1) v |= (uint64_t)rd(dev, f->offset + 4u) << 32;
  return v;
}
#endif

static rl_status command(const rl_device *dev, uint32_t bits) {
  if (dev == NULL) return RL_ERR_ARG;
  wr(dev, RL_CTRL_CONTROL_OFFSET, bits);
  return RL_OK;
}

rl_status rl_monitor_clear(const rl_device *dev) {
#if RL_LAYOUT_HAS_MONITOR
  return command(dev, RL_CTRL_CONTROL_CLEAR_MASK);
#else
  (void)dev;
  return RL_ERR_UNSUPPORTED;
#endif
}

rl_status rl_counters_clear(const rl_device *dev) { return command(dev, RL_CTRL_CONTROL_CLEAR_COUNTERS_MASK); }

rl_status rl_monitor_snapshot(const rl_device *dev, int clear, rl_monitor *out) {
#if RL_LAYOUT_HAS_MONITOR
  uint32_t polls = 0, before;
  int j, b;
  if (dev == NULL || out == NULL) return RL_ERR_ARG;
  command(dev, RL_CTRL_CONTROL_SNAPSHOT_MASK | (clear ? RL_CTRL_CONTROL_CLEAR_MASK : 0u));
  while ((rd(dev, RL_CTRL_STATUS_OFFSET) & RL_CTRL_STATUS_SNAPSHOT_READY_MASK) == 0u)
    if (++polls >= dev->poll_limit) return RL_ERR_TIMEOUT;
  /* Another master may snapshot meanwhile: the count before and after tells, and the bank is read again. */
  do {
    before = rd(dev, RL_MONITOR_SNAPSHOT_COUNT_OFFSET);
    for (j = 0; j < RL_JOINTS; j++) {
      const rl_figure_layout *f = rl_figures[j];
      rl_joint_figures *o = &out->joint[j];
      o->samples = figure_count(dev, &f[RL_FIG_SAMPLES]);
      o->out_of_range_samples = figure_count(dev, &f[RL_FIG_OUT_OF_RANGE_SAMPLES]);
      o->peak_torque = figure_value(dev, &f[RL_FIG_PEAK_TORQUE]);
      o->min_torque = figure_value(dev, &f[RL_FIG_MIN_TORQUE]);
      o->repeated_peak_samples = figure_count(dev, &f[RL_FIG_REPEATED_PEAK_SAMPLES]);
      o->momentary_peak_events = figure_count(dev, &f[RL_FIG_MOMENTARY_PEAK_EVENTS]);
      o->last_event_peak_abs = figure_value(dev, &f[RL_FIG_LAST_EVENT_PEAK_ABS]);
      o->last_event_duration = figure_count(dev, &f[RL_FIG_LAST_EVENT_DURATION]);
      o->last_event_speed_abs = figure_value(dev, &f[RL_FIG_LAST_EVENT_SPEED_ABS]);
      o->flags = rd(dev, f[RL_FIG_FLAGS].offset);
      o->damage_sum = figure_value(dev, &f[RL_FIG_DAMAGE_SUM]);
      o->speed_sum = figure_value(dev, &f[RL_FIG_SPEED_SUM]);
      o->histogram_bins = rl_joint_bins[j];
      for (b = 0; b < RL_HISTOGRAM_BINS; b++)
        o->histogram[b] = b < (int)rl_joint_bins[j] ? figure_count(dev, &f[RL_FIG_HISTOGRAM_0 + b]) : 0u;
    }
    out->snapshot_count = rd(dev, RL_MONITOR_SNAPSHOT_COUNT_OFFSET);
    if (++polls >= dev->poll_limit) return RL_ERR_TIMEOUT;
  } while (out->snapshot_count != before);
  return RL_OK;
#else
  (void)dev;
  (void)clear;
  (void)out;
  return RL_ERR_UNSUPPORTED;
#endif
}

/* ---- register-driven sample mode ---- */

/* The sample block's per-joint codes: joint j at word 0's offset + 4 j; a code wider than 32 bits has its
 * word 1 of every joint after word 0 of every joint. */
#if defined(RL_SAMPLE_Q_J1_OFFSET) && defined(RL_SAMPLE_QD_J1_OFFSET) && defined(RL_SAMPLE_QDD_J1_OFFSET)
#define RL_SAMPLE_MODE 1
#if defined(RL_SAMPLE_TAU_J1_OFFSET)
#define RL_SAMPLE_TAU0 RL_SAMPLE_TAU_J1_OFFSET
#define RL_SAMPLE_TAU_WORDS 1
#else
#define RL_SAMPLE_TAU0 RL_SAMPLE_TAU_J1_W0_OFFSET
#define RL_SAMPLE_TAU_WORDS 2
#endif
#else
#define RL_SAMPLE_MODE 0 /* codes wider than 32 bits at the inputs: not supported by this driver */
#endif

rl_status rl_sample(const rl_device *dev, const double q[RL_JOINTS], const double qd[RL_JOINTS],
                    const double qdd[RL_JOINTS], double tau[RL_JOINTS], uint32_t *out_of_range) {
#if RL_SAMPLE_MODE
  uint32_t aq[RL_JOINTS], polls = 0;
  int32_t aqd[RL_JOINTS], aqdd[RL_JOINTS];
  int j;
  rl_status s;
  if (dev == NULL || q == NULL || qd == NULL || qdd == NULL || tau == NULL) return RL_ERR_ARG;
  for (j = 0; j < RL_JOINTS; j++) {
    if ((s = rl_si_to_angle(q[j], &aq[j])) != RL_OK) return s;
    if ((s = rl_si_to_velocity(qd[j], &aqd[j])) != RL_OK) return s;
    if ((s = rl_si_to_acceleration(qdd[j], &aqdd[j])) != RL_OK) return s;
  }
  for (j = 0; j < RL_JOINTS; j++) {
    uint32_t at = 4u * (uint32_t)j;
    wr(dev, RL_SAMPLE_Q_J1_OFFSET + at, aq[j]);
    wr(dev, RL_SAMPLE_QD_J1_OFFSET + at, (uint32_t)aqd[j] & RL_SAMPLE_QD_J1_VALUE_MASK);
    wr(dev, RL_SAMPLE_QDD_J1_OFFSET + at, (uint32_t)aqdd[j] & RL_SAMPLE_QDD_J1_VALUE_MASK);
  }
  wr(dev, RL_SAMPLE_START_OFFSET, RL_SAMPLE_START_START_MASK);
  while ((rd(dev, RL_SAMPLE_STATUS_OFFSET) & RL_SAMPLE_STATUS_DONE_MASK) == 0u)
    if (++polls >= dev->poll_limit) return RL_ERR_TIMEOUT;
  for (j = 0; j < RL_JOINTS; j++) {
    uint64_t raw = rd(dev, RL_SAMPLE_TAU0 + 4u * (uint32_t)j);
    if (RL_SAMPLE_TAU_WORDS > 1) raw |= (uint64_t)rd(dev, RL_SAMPLE_TAU0 + 4u * (uint32_t)(RL_JOINTS + j)) << 32;
    tau[j] = rl_torque_to_si((int64_t)raw);
  }
  if (out_of_range != NULL) *out_of_range = rd(dev, RL_SAMPLE_FLAGS_OFFSET);
  return RL_OK;
#else
  (void)dev;
  (void)q;
  (void)qd;
  (void)qdd;
  (void)tau;
  (void)out_of_range;
  return RL_ERR_UNSUPPORTED;
#endif
}
