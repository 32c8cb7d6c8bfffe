/*
 * reducer_load.h: C99 driver of the reducer-load core's register map (docs/driver.md).
 *
 * Portable C99, no OS, no heap: the platform supplies two bus functions (read32, write32 at byte offsets
 * from the core's base) and a context pointer. Every design-specific fact (offsets, fields, formats, scales,
 * the joint count, the design hash) comes from the generated headers reducer_load_regs.h and
 * reducer_load_layout.h ("run emit" writes them beside the Verilog); rebuild the driver with the headers of
 * the design it talks to. Every function returns an rl_status (RL_OK = 0, errors negative).
 */
#ifndef REDUCER_LOAD_H
#define REDUCER_LOAD_H

#include <stdint.h>

#include "reducer_load_regs.h"
#include "reducer_load_layout.h"

/* The joint count (a plain int constant): the register header's RL_JOINTS if it has one, else the layout's. */
#ifndef RL_JOINTS
#define RL_JOINTS RL_LAYOUT_JOINTS
#endif

#if RL_LAYOUT_JOINTS != RL_JOINTS || RL_LAYOUT_JOINTS != RL_ID_SHAPE_JOINTS_RESET
#error "reducer_load_layout.h and reducer_load_regs.h are of different designs"
#endif

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  RL_OK = 0,
  RL_ERR_ARG = -1,         /* a null pointer, a joint index beyond RL_JOINTS, a non-unit quaternion */
  RL_ERR_MAGIC = -2,       /* the identification block's magic is not "RLOD": no core at this address */
  RL_ERR_VERSION = -3,     /* another generator version than the headers' */
  RL_ERR_DESIGN = -4,      /* another design hash than the headers': rebuild with that design's headers */
  RL_ERR_SHAPE = -5,       /* another joint count or port format than the headers' */
  RL_ERR_RANGE = -6,       /* a value beyond the declared range (the hardware would clamp it): refused */
  RL_ERR_NOT_FINITE = -7,  /* NaN or infinity */
  RL_ERR_TIMEOUT = -8,     /* a status bit did not come within the device's poll limit */
  RL_ERR_UNSUPPORTED = -9  /* the design has no such block (no monitor, no payload, no sample mode) */
} rl_status;

/* Byte offsets from the core's base; 32-bit registers, written whole. */
typedef uint32_t (*rl_read32_fn)(void *ctx, uint32_t byte_offset);
typedef void (*rl_write32_fn)(void *ctx, uint32_t byte_offset, uint32_t value);

typedef struct {
  rl_read32_fn read32;
  rl_write32_fn write32;
  void *ctx;
  uint32_t poll_limit; /* status reads before RL_ERR_TIMEOUT (rl_init sets RL_DEFAULT_POLL_LIMIT) */
} rl_device;

#define RL_DEFAULT_POLL_LIMIT 100000u

/* What the identification block says (filled by rl_init even when a check fails). */
typedef struct {
  uint32_t magic, version, design_hash, joints, clocks_per_sample;
} rl_identity;

/* A payload as the payload registers take it: mass (kg), centre of mass (m, payload frame) and the inertia
 * tensor about the centre of mass in the payload frame's axes (kg m^2): xx, xy, xz, yy, yz, zz. */
typedef struct {
  double mass;
  double com[3];
  double inertia[6];
} rl_payload;

enum { RL_IXX = 0, RL_IXY = 1, RL_IXZ = 2, RL_IYY = 3, RL_IYZ = 4, RL_IZZ = 5 };

/* ABB-style load data (RAPID loaddata): mass (kg), centre of gravity cog (mm, payload frame), the axes of
 * moment aom as a unit quaternion q1 (scalar), q2, q3, q4 (the principal axes in the payload frame), and the
 * principal moments of inertia ix, iy, iz (kg m^2) about the centre of gravity along those axes. */
typedef struct {
  double mass;
  double cog_mm[3];
  double aom[4];
  double ix, iy, iz;
} rl_abb_loaddata;

/* One joint's monitor figures after a snapshot: counts as integers, torques and speeds in SI units. */
typedef struct {
  uint64_t samples;              /* in-range valid samples since clear */
  uint64_t out_of_range_samples; /* valid samples flagged out of range */
  double peak_torque;            /* N m (N: prismatic), largest signed torque since clear */
  double min_torque;             /* N m, smallest signed torque since clear */
  uint64_t repeated_peak_samples;
  uint64_t momentary_peak_events;
  double last_event_peak_abs;    /* N m */
  uint64_t last_event_duration;  /* samples */
  double last_event_speed_abs;   /* rad/s (m/s: prismatic) */
  uint32_t flags;                /* bit 0 repeated peak seen, 1 momentary peak seen, 2 in event, 3 saturated */
  double damage_sum;             /* sum |qd code| x power, in codes (see docs/monitor.md) */
  double speed_sum;              /* sum |qd| in rad/s (x sample period = rad travelled) */
  unsigned histogram_bins;       /* this joint's bins (RL_HISTOGRAM_BINS is the most of any joint) */
  uint64_t histogram[RL_HISTOGRAM_BINS > 0 ? RL_HISTOGRAM_BINS : 1];
} rl_joint_figures;

typedef struct {
  uint32_t snapshot_count;
  rl_joint_figures joint[RL_JOINTS];
} rl_monitor;

/* Connect to the core and check its identification block against the headers: magic, version, design
 * hash, joint count, port formats. `id` may be null. */
rl_status rl_init(rl_device *dev, rl_read32_fn read32, rl_write32_fn write32, void *ctx, rl_identity *id);

/* Convert codes and values with the headers' formats. */
double rl_torque_to_si(int64_t code); /* a tau port code (sign-extended from its width) -> N m */
rl_status rl_si_to_angle(double rad, uint32_t *code); /* any real angle -> binary angle code (wraps a turn) */
rl_status rl_si_to_velocity(double rad_s, int32_t *code);     /* refused beyond the port's format */
rl_status rl_si_to_acceleration(double rad_s2, int32_t *code);

/* Payload registers: stage (write), commit (the staged payload applies from the next sample on), read. */
rl_status rl_payload_write(const rl_device *dev, const rl_payload *p);
rl_status rl_payload_from_abb(const rl_abb_loaddata *l, rl_payload *p);
rl_status rl_payload_write_abb(const rl_device *dev, const rl_abb_loaddata *l);
rl_status rl_payload_read_staged(const rl_device *dev, rl_payload *p);
rl_status rl_gravity_write(const rl_device *dev, const double g[3]);
rl_status rl_payload_commit(const rl_device *dev);
rl_status rl_payload_sequence(const rl_device *dev, uint32_t *sequence);

/* Monitor: snapshot (with clear: read-and-reset), wait for it, read every joint in SI units. */
rl_status rl_monitor_snapshot(const rl_device *dev, int clear, rl_monitor *out);
rl_status rl_monitor_clear(const rl_device *dev);
rl_status rl_counters_clear(const rl_device *dev);

/* Register-driven sample mode: one sample (rad, rad/s, rad/s^2 per joint) in, torques (N m) out. */
rl_status rl_sample(const rl_device *dev, const double q[RL_JOINTS], const double qd[RL_JOINTS],
                    const double qdd[RL_JOINTS], double tau[RL_JOINTS], uint32_t *out_of_range);

const char *rl_status_text(rl_status s);

#ifdef __cplusplus
}
#endif

#endif /* REDUCER_LOAD_H */
