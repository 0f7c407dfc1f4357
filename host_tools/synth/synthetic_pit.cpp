#include "synth/synthetic_pit.h"

#include <cmath>
#include <cstdio>

#include "pitvol/splitmix64.h"

namespace pv::synth {

namespace {

constexpr double kPi = 3.14159265358979323846;

double deg(double d) { return d * kPi / 180.0; }

}  // namespace

double exact_volume_cm3(const PitSpec &s) {
  const double a = s.radius_bottom_mm, b = s.radius_top_mm;
  return kPi * s.depth_mm / 3.0 * (a * a + a * b + b * b) / 1000.0;
}

PitScan::PitScan(const PitSpec &s) : s_(s), state_(s.seed * 0x9e3779b97f4a7c15ull + 1) {
  // R = Rz(yaw) * tilt about a horizontal axis at tilt_azimuth * (flip).
  const double t = deg(s.tilt_deg), az = deg(s.tilt_azimuth_deg), yw = deg(s.yaw_deg);
  const double ax = std::cos(az), ay = std::sin(az);  // tilt axis (horizontal)
  const double c = std::cos(t), sn = std::sin(t), C = 1 - c;
  const double tilt[9] = {c + ax * ax * C, ax * ay * C, ay * sn,
                          ax * ay * C, c + ay * ay * C, -ax * sn,
                          -ay * sn, ax * sn, c};
  const double cy = std::cos(yw), sy = std::sin(yw);
  const double yaw[9] = {cy, -sy, 0, sy, cy, 0, 0, 0, 1};
  double m[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      m[3 * i + j] = 0;
      for (int k = 0; k < 3; ++k) m[3 * i + j] += tilt[3 * i + k] * yaw[3 * k + j];
    }
  const double f = s.upside_down ? -1.0 : 1.0;  // half turn about X
  for (int i = 0; i < 3; ++i) {
    R_[3 * i + 0] = m[3 * i + 0];
    R_[3 * i + 1] = m[3 * i + 1] * f;
    R_[3 * i + 2] = m[3 * i + 2] * f;
  }
}

double PitScan::uniform() {
  return pv_splitmix64_unit(&state_);
}

double PitScan::gaussian() {
  const double u1 = uniform() + 1e-300, u2 = uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2 * kPi * u2);
}

// A point in the pit frame: floor at z = 0, rim at z = depth, axis on Z.
void PitScan::surface_point(double *p) {
  const double a = s_.radius_bottom_mm, b = s_.radius_top_mm, h = s_.depth_mm;
  const double u = uniform();
  const double th = 2 * kPi * uniform();
  const double ground = s_.ground_width_mm > 0 ? s_.ground_share : 0.0;
  if (u < s_.stray_share) {  // far stray, anywhere in a box around the pit
    p[0] = (uniform() - 0.5) * 4 * b;
    p[1] = (uniform() - 0.5) * 4 * b;
    p[2] = (uniform() - 0.3) * 2 * h;
    return;
  }
  if (u < s_.stray_share + s_.multipath_share) {  // floating inside the void
    const double z = h * uniform();
    const double r = (a + (b - a) * z / h) * std::sqrt(uniform());
    p[0] = r * std::cos(th);
    p[1] = r * std::sin(th);
    p[2] = z;
    return;
  }
  const double v = uniform();
  const double n = s_.noise_mm * gaussian();
  if (v < s_.floor_share) {  // floor: uniform over the disc
    const double r = a * std::sqrt(uniform());
    p[0] = r * std::cos(th);
    p[1] = r * std::sin(th);
    p[2] = n;
    return;
  }
  if (v < s_.floor_share + ground) {  // ground ring around the rim
    const double r0 = b, r1 = b + s_.ground_width_mm;
    const double r = std::sqrt(r0 * r0 + (r1 * r1 - r0 * r0) * uniform());
    p[0] = r * std::cos(th);
    p[1] = r * std::sin(th);
    p[2] = h + n;
    return;
  }
  // Wall: a mix of uniform height and a density that grows toward the
  // floor (overlapping views), so the upper wall is sparser but not empty.
  const double w = uniform();
  const double zz = uniform() < 0.4 ? h * w : h * (1.0 - std::sqrt(w));
  const double r = a + (b - a) * zz / h + n;
  p[0] = r * std::cos(th);
  p[1] = r * std::sin(th);
  p[2] = zz;
}

pv_point_t PitScan::next() {
  double p[3];
  surface_point(p);
  const double *R = R_;
  const double x = R[0] * p[0] + R[1] * p[1] + R[2] * p[2] + s_.offset_mm[0];
  const double y = R[3] * p[0] + R[4] * p[1] + R[5] * p[2] + s_.offset_mm[1];
  const double z = R[6] * p[0] + R[7] * p[1] + R[8] * p[2] + s_.offset_mm[2];
  return pv_point_t{float(x), float(y), float(z)};
}

bool write_scan_ply(const char *path, const PitSpec &s, uint64_t n) {
  FILE *f = std::fopen(path, "wb");
  if (f == nullptr) return false;
  std::fprintf(f,
               "ply\nformat binary_little_endian 1.0\n"
               "comment pitvol synthetic pit: radius %.3f mm depth %.3f mm seed %llu\n"
               "comment exact_volume_cm3 %.6f\n"
               "element vertex %llu\nproperty float x\nproperty float y\nproperty float z\n"
               "end_header\n",
               s.radius_top_mm, s.depth_mm, (unsigned long long)s.seed, exact_volume_cm3(s),
               (unsigned long long)n);
  PitScan scan(s);
  bool ok = true;
  for (uint64_t i = 0; i < n; ++i) {
    const pv_point_t p = scan.next();  // x86 and aarch64 are little endian
    ok = ok && std::fwrite(&p, sizeof p, 1, f) == 1;
  }
  return std::fclose(f) == 0 && ok;
}

}  // namespace pv::synth
