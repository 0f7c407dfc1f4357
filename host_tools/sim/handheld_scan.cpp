// A simulated handheld structured-light scan: Embree 3 ray casting against
// the pit's `scanned` mesh from poses on a path of loops above the rim.
//
// The path (pit frame: axis on Z, rim plane at rim_z_mm):
// - a "pass" is kLoops loops around the axis, parameterised by u in
//   [0, kLoops) (one unit = one loop); frame i of a pass sits at
//   u = i / frames_per_loop;
// - the scanner radius swings smoothly between 0.3 and 1.2 x the pit radius
//   (one slow in/out cycle per pass), its height between 150 and 350 mm
//   above the rim plane, both with smooth value-noise jitter from the seed;
// - it aims at a point that blends smoothly between the axis (at a depth
//   that wanders from near the rim to near the floor) and the far wall (at
//   a wandering depth), with a little roll;
// - frames_per_loop is chosen at construction from a few probe frames (hit
//   rays only, no random draws) so that one pass yields about 1.3 x
//   target_points whatever the pit size; should a pass end short anyway,
//   another pass with fresh jitter follows (at most kMaxPasses).
// Per frame: a rays_x x rays_y pinhole grid over fov_deg (horizontal),
// rtcIntersect8 packets, first hit only; the hit point is recomputed on
// the triangle Embree reports, in double precision in this file, so the
// scan has the same bits on every x86-64 (Embree's SSE2 to AVX-512
// kernels, glibc's libm with and without FMA: tests/unit/sim). A hit
// returns with probability cos(i) (the projected pattern dims and
// stretches at incidence i) and never beyond
// 82 deg, which is what leaves steep upper walls sparse next to the floor.
// Then: a stray_share of returns become far strays (uniform in a box 2-3x
// the pit), a multipath_share become points 2..40 mm in front of the hit on
// the same ray (kept below the rim plane for hits in the void), the rest get
// Gaussian range noise (noise_mm) along the ray. Random draws come from
// splitmix64 streams derived from the seed (transform, stray box, path,
// noise); Embree runs on one thread.
// Hits are front faces only: a ray that meets a wall or floor triangle from
// the soil side went through ground that is not in the mesh (pits without a
// ground ring, or beyond its outer radius), so it is blocked and emits
// nothing. Triangles in the rim plane (the ground ring) are always seen
// from above.
#include "sim/handheld_scan.h"
#include "pitvol/splitmix64.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace pv::sim {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kLoops = 4;            // loops per pass
constexpr int kKnotsPerLoop = 8;     // value-noise knots per loop
constexpr int kMaxPasses = 8;        // path end
constexpr int kProbeFrames = 24;     // frames cast to size the path
constexpr double kPathMargin = 1.3;  // one pass yields ~1.3 x target
constexpr double kGrazingDeg = 82.0; // no return beyond this incidence
constexpr double kIncidenceExp = 1.0;

struct V3 {
  double x, y, z;
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double norm(V3 a) { return std::sqrt(dot(a, a)); }
V3 normalized(V3 a) {
  const double n = norm(a);
  return n > 0.0 ? (1.0 / n) * a : a;
}

// The point where the ray o + t dir meets the plane of triangle abc, as
// barycentrics on the triangle (Moller-Trumbore in double precision). Only
// +, -, *, / in a fixed order: the same bits on every x86-64 (the sim is
// built without floating-point contraction).
V3 ray_triangle_point(V3 o, V3 dir, V3 a, V3 b, V3 c) {
  const V3 e1 = b - a, e2 = c - a;
  const V3 pv = cross(dir, e2);
  const double det = dot(e1, pv);
  if (det == 0.0) return a;  // parallel to the plane: Embree reports no such hit
  const V3 tv = o - a;
  const double u = dot(tv, pv) / det;
  const double v = dot(dir, cross(tv, e1)) / det;
  return (1.0 - u - v) * a + u * b + v * c;
}

// splitmix64 + Box-Muller, the same draws everywhere.
struct Rng {
  uint64_t s;
  uint64_t next() { return pv_splitmix64_next(&s); }
  double uniform() {  // (0, 1)
    return (static_cast<double>(next() >> 11) + 0.5) * (1.0 / 9007199254740992.0);
  }
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  double gauss() {
    const double u1 = uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
  }
};

uint64_t derive_seed(uint64_t seed, uint64_t stream) {
  Rng r{seed ^ (stream * 0xD1B54A32D192ED03ull)};
  r.next();
  return r.next();
}

// Smooth 1-D value noise in [-1, 1]: knots every 1/kKnotsPerLoop loop,
// smoothstep between them.
struct SmoothNoise {
  std::vector<double> knots;
  void draw(Rng &rng, size_t n) {
    knots.resize(n);
    for (double &k : knots) k = rng.uniform(-1.0, 1.0);
  }
  double at(double u) const {
    const double x = std::max(0.0, u * kKnotsPerLoop);
    size_t i = static_cast<size_t>(x);
    if (i + 1 >= knots.size()) return knots.back();
    const double f = x - static_cast<double>(i);
    const double s = f * f * (3.0 - 2.0 * f);
    return knots[i] + (knots[i + 1] - knots[i]) * s;
  }
};

struct PassJitter {
  double phi0, dir, a_r, a_h;
  SmoothNoise ang, rad, hgt, w, ax_depth, ax_x, ax_y, wall_ang, wall_depth, roll;
};

struct Pose {
  V3 pos, fwd, right, up;
};

void embree_error(void *, RTCError code, const char *str) {
  std::fprintf(stderr, "embree error %d: %s\n", static_cast<int>(code), str ? str : "");
}

// An Embree device and the committed scene of one mesh. The scene is only
// read once committed, so scans of the same mesh one after the other (the
// passes of a long scan) share it instead of building it again: the last
// one built is kept, keyed by the mesh's bytes and Embree's configuration.
struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  uint64_t key = 0;
  EmbreeScene() = default;
  EmbreeScene(const EmbreeScene &) = delete;
  EmbreeScene &operator=(const EmbreeScene &) = delete;
  ~EmbreeScene() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

uint64_t fnv(uint64_t h, const void *p, size_t n) {
  const auto *b = static_cast<const unsigned char *>(p);
  for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
  return h;
}

std::shared_ptr<EmbreeScene> &last_scene() {
  static std::shared_ptr<EmbreeScene> s;
  return s;
}

}  // namespace

struct HandheldScan::Impl {
  ScanParams p;
  // Mesh copy (double precision hit points, face orientation).
  std::vector<float> xyz;
  std::vector<uint32_t> tri;
  std::vector<uint8_t> ground_tri;  // triangle lies in the rim plane

  std::shared_ptr<EmbreeScene> embree;
  RTCScene scene = nullptr;

  // Pit frame measures.
  double rim = 0.0, zfloor = 0.0, depth = 1.0, radius = 1.0;
  // Stray box.
  V3 box_lo{}, box_hi{};
  // Transform world = R * pit + t.
  double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double t[3] = {0, 0, 0};
  double tilt = 0.0;

  Rng path_rng{}, noise_rng{};
  // Wall coverage: a cell per wall triangle (-1: not wall), returns per cell.
  std::vector<int16_t> tri_cell;
  std::vector<int16_t> tri_rim;  // the rim sector, after the wall's cells
  std::vector<double> cell_area;
  std::vector<uint32_t> cell_hits;
  std::vector<DropoutPatch> patches;
  PassJitter jit{};
  int pass = 0;
  uint64_t frame_in_pass = 0;
  uint64_t frames_per_loop = 90;
  uint64_t frame_index = 0;
  uint64_t emitted = 0;
  bool done = false;


  void build_scene() {
    // Embree picks its kernels by the CPU, and their u, v, t differ in the
    // last bits; the hits are recomputed (ray_triangle_point), so the scan
    // does not depend on them. PITVOL_SIM_ISA caps the kernels (sse2,
    // sse4.2, avx, avx2, avx512) for the tests that show it.
    const char *isa = std::getenv("PITVOL_SIM_ISA");
    const std::string config =
        std::string("threads=1") + (isa && *isa ? std::string(",max_isa=") + isa : "");
    uint64_t key = fnv(0xcbf29ce484222325ull, config.data(), config.size());
    key = fnv(key, xyz.data(), xyz.size() * sizeof(float));
    key = fnv(key, tri.data(), tri.size() * sizeof(uint32_t));
    std::shared_ptr<EmbreeScene> &last = last_scene();
    if (last && last->key == key) {
      embree = last;
      scene = embree->scene;
      return;
    }
    last.reset();  // free the previous mesh's scene before building this one
    embree = std::make_shared<EmbreeScene>();
    embree->key = key;
    RTCDevice &device = embree->device;
    device = rtcNewDevice(config.c_str());
    if (!device) throw std::runtime_error("embree: rtcNewDevice(\"" + config + "\") failed");
    rtcSetDeviceErrorFunction(device, embree_error, nullptr);
    scene = embree->scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    const size_t nv = xyz.size() / 3, nt = tri.size() / 3;
    if (nv > 0 && nt > 0) {
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto *vb = static_cast<float *>(rtcSetNewGeometryBuffer(
          g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
      auto *ib = static_cast<unsigned *>(rtcSetNewGeometryBuffer(
          g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nt));
      if (!vb || !ib) throw std::runtime_error("embree: buffer allocation failed");
      std::copy(xyz.begin(), xyz.end(), vb);
      std::copy(tri.begin(), tri.end(), ib);
      rtcCommitGeometry(g);
      rtcAttachGeometry(scene, g);
      rtcReleaseGeometry(g);
    }
    rtcCommitScene(scene);
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE)
      throw std::runtime_error("embree: scene build failed");
    last = embree;
  }

  V3 vertex(uint32_t i) const {
    return {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
  }

  void draw_pass() {
    Rng &r = path_rng;
    jit.phi0 = r.uniform(0.0, 2.0 * kPi);
    jit.dir = r.uniform() < 0.5 ? -1.0 : 1.0;
    jit.a_r = r.uniform(0.0, 2.0 * kPi);
    jit.a_h = r.uniform(0.0, 2.0 * kPi);
    const size_t n = static_cast<size_t>(kLoops * kKnotsPerLoop + 2);
    for (SmoothNoise *s : {&jit.ang, &jit.rad, &jit.hgt, &jit.w, &jit.ax_depth, &jit.ax_x,
                           &jit.ax_y, &jit.wall_ang, &jit.wall_depth, &jit.roll})
      s->draw(r, n);
  }

  Pose pose(double u) const {
    const PassJitter &j = jit;
    // Circling, or sweeping back and forth over a partial arc (one loop of
    // u per sweep end to end).
    const double phi = p.path_arc_deg >= 360.0
        ? j.phi0 + j.dir * 2.0 * kPi * u + 0.15 * j.ang.at(u)
        : j.phi0 + (std::max(0.0, p.path_arc_deg) * kPi / 180.0) * (0.5 - 0.5 * std::cos(kPi * u)) +
              0.15 * j.ang.at(u);
    double rf = 0.75 + 0.40 * std::cos(2.0 * kPi * u / kLoops + j.a_r) + 0.10 * j.rad.at(u);
    rf = std::clamp(rf, 0.3, 1.2);
    // An operator who walks only part of the way round stays at the rim
    // (the scanner does not reach over the pit).
    if (p.path_arc_deg < 360.0)
      rf = std::clamp(1.1 + 0.1 * std::cos(2.0 * kPi * u / kLoops + j.a_r) + 0.05 * j.rad.at(u),
                      1.0, 1.25);
    double h = 250.0 + 75.0 * std::sin(2.0 * kPi * 1.5 * u / kLoops + j.a_h) + 30.0 * j.hgt.at(u);
    h = std::clamp(h, 150.0, 350.0);
    const V3 pos{rf * radius * std::cos(phi), rf * radius * std::sin(phi), rim + h};

    // Target: the axis at a wandering depth, or the far wall.
    const V3 axis_pt{0.1 * radius * j.ax_x.at(u), 0.1 * radius * j.ax_y.at(u),
                     zfloor + depth * (0.05 + 0.85 * (0.5 + 0.5 * j.ax_depth.at(u)))};
    const double wa = phi + kPi + 0.4 * j.wall_ang.at(u);
    const V3 wall_pt{0.9 * radius * std::cos(wa), 0.9 * radius * std::sin(wa),
                     zfloor + depth * (0.15 + 0.7 * (0.5 + 0.5 * j.wall_depth.at(u)))};
    // Along a partial arc the operator aims across at the far wall (never
    // down and back at the wall below them).
    const double w = p.path_arc_deg < 360.0 ? std::clamp(0.85 + 0.3 * j.w.at(u), 0.6, 1.0)
                                            : std::clamp(0.5 + 0.8 * j.w.at(u), 0.0, 1.0);
    V3 target = (1.0 - w) * axis_pt + w * wall_pt;
    V3 at = pos;
    if (p.outside_views > 0.0 && 0.5 + 0.5 * j.w.at(u) < p.outside_views) {
      const double out = 1.35 + 0.2 * j.rad.at(u);
      at = V3{out * radius * std::cos(phi), out * radius * std::sin(phi), rim + 60.0 + 40.0 * j.hgt.at(u)};
      target = V3{radius * std::cos(phi), radius * std::sin(phi), rim - 0.25 * depth};
    }

    Pose ps;
    ps.pos = at;
    ps.fwd = normalized(target - at);
    V3 right = cross(ps.fwd, V3{0, 0, 1});
    if (norm(right) < 1e-6) right = V3{-std::sin(phi), std::cos(phi), 0.0};
    right = normalized(right);
    V3 up = cross(right, ps.fwd);
    const double roll = 0.17 * j.roll.at(u);  // about +-10 deg
    const double c = std::cos(roll), s = std::sin(roll);
    ps.right = c * right + s * up;
    ps.up = c * up - s * right;
    return ps;
  }

  // Casts one frame in packets of 8 rays (rtcIntersect8, row-major ray
  // order); calls emit(surface point, ray dir, distance, cos incidence,
  // triangle) per valid hit, in ray order.
  template <class F>
  void cast(const Pose &ps, F &&emit) const {
    const uint32_t nx = p.rays_x, ny = p.rays_y;
    if (nx == 0 || ny == 0) return;
    const double th = std::tan(0.5 * std::clamp(p.fov_deg, 1.0, 170.0) * kPi / 180.0);
    const double tv = th * static_cast<double>(ny) / static_cast<double>(nx);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    const float ox = static_cast<float>(ps.pos.x), oy = static_cast<float>(ps.pos.y),
                oz = static_cast<float>(ps.pos.z);
    const V3 o{ox, oy, oz};  // the origin exactly as Embree sees it
    const uint32_t n = nx * ny;
    alignas(32) RTCRayHit8 rh;
    alignas(32) int valid[8];
    for (uint32_t k0 = 0; k0 < n; k0 += 8) {
      for (uint32_t l = 0; l < 8; ++l) {
        const uint32_t k = k0 + l;
        valid[l] = k < n ? -1 : 0;
        const uint32_t ix = k < n ? k % nx : 0, iy = k < n ? k / nx : 0;
        const double px = ((ix + 0.5) / nx * 2.0 - 1.0) * th;
        const double py = ((iy + 0.5) / ny * 2.0 - 1.0) * tv;
        const V3 d = normalized(ps.fwd + px * ps.right + py * ps.up);
        rh.ray.org_x[l] = ox;
        rh.ray.org_y[l] = oy;
        rh.ray.org_z[l] = oz;
        rh.ray.tnear[l] = 0.0f;
        rh.ray.dir_x[l] = static_cast<float>(d.x);
        rh.ray.dir_y[l] = static_cast<float>(d.y);
        rh.ray.dir_z[l] = static_cast<float>(d.z);
        rh.ray.time[l] = 0.0f;
        rh.ray.tfar[l] = INFINITY;
        rh.ray.mask[l] = 0xFFFFFFFFu;
        rh.ray.id[l] = k;
        rh.ray.flags[l] = 0;
        rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID[l] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect8(valid, scene, &ctx, &rh);
      for (uint32_t l = 0; l < 8; ++l) {
        if (!valid[l] || rh.hit.geomID[l] == RTC_INVALID_GEOMETRY_ID) continue;
        const uint32_t pid = rh.hit.primID[l];
        const V3 a = vertex(tri[3 * pid]), b = vertex(tri[3 * pid + 1]),
                 c = vertex(tri[3 * pid + 2]);
        const V3 d = normalized(V3{rh.ray.dir_x[l], rh.ray.dir_y[l], rh.ray.dir_z[l]});
        double cos_i = dot(normalized(cross(b - a, c - a)), d);
        if (ground_tri[pid]) {
          cos_i = std::fabs(cos_i);  // the ground ring is always seen from above
        } else if (cos_i <= 0.0) {
          continue;  // outward (into the soil) normal: front faces face the void
        }
        // The hit recomputed on the triangle Embree reports, in double
        // precision from the ray as Embree saw it: Embree's own u, v, t
        // carry last bits that depend on its SIMD kernels (SSE2, AVX2 and
        // AVX-512 gave three scans from one seed), these do not.
        const V3 s = ray_triangle_point(o, V3{rh.ray.dir_x[l], rh.ray.dir_y[l], rh.ray.dir_z[l]},
                                        a, b, c);
        emit(s, d, norm(s - o), cos_i, pid);
      }
    }
  }

  // Structured light returns less as the incidence grows (the projected
  // pattern stretches and dims): a Lambertian cos factor, and nothing beyond
  // kGrazingDeg.
  static double keep_probability(double cos_i) {
    static const double cos_max = std::cos(kGrazingDeg * kPi / 180.0);
    if (cos_i <= cos_max) return 0.0;
    return std::min(1.0, std::pow(cos_i, kIncidenceExp));
  }

  // Dropout patch centres uniform by area on the wall and floor (the
  // non-ground triangles), from their own stream.
  void draw_patches() {
    patches.clear();
    if (p.dropout_patches == 0) return;
    std::vector<double> cum;
    std::vector<uint32_t> ids;
    double total = 0.0;
    for (uint32_t k = 0; k < tri.size() / 3; ++k) {
      if (ground_tri[k]) continue;
      const V3 a = vertex(tri[3 * k]), b = vertex(tri[3 * k + 1]), c = vertex(tri[3 * k + 2]);
      total += 0.5 * norm(cross(b - a, c - a));
      cum.push_back(total);
      ids.push_back(k);
    }
    if (ids.empty()) return;
    Rng r{derive_seed(p.seed, 5)};
    const double lo = std::max(0.0, p.dropout_radius_min_mm);
    const double hi = std::max(lo, p.dropout_radius_max_mm);
    for (uint32_t i = 0; i < p.dropout_patches; ++i) {
      const double at = r.uniform(0.0, total);
      const size_t pos = std::min(ids.size() - 1, static_cast<size_t>(
          std::lower_bound(cum.begin(), cum.end(), at) - cum.begin()));
      const uint32_t k = ids[pos];
      double b1 = r.uniform(), b2 = r.uniform();
      if (b1 + b2 > 1.0) {
        b1 = 1.0 - b1;
        b2 = 1.0 - b2;
      }
      const V3 a = vertex(tri[3 * k]), b = vertex(tri[3 * k + 1]), c = vertex(tri[3 * k + 2]);
      const V3 q = a + b1 * (b - a) + b2 * (c - a);
      patches.push_back({q.x, q.y, q.z, r.uniform(lo, hi)});
    }
  }

  // The wall cells of WallCoverage (reporting only: no draw, no point
  // depends on them).
  void build_cells() {
    constexpr int kSectors = kCoverageSectors, kBands = kCoverageBands;
    constexpr int kRimCells = kSectors * kBands;  // the rim's sectors follow
    const size_t nt = tri.size() / 3;
    tri_cell.assign(nt, -1);
    tri_rim.assign(nt, -1);
    cell_area.assign(kRimCells + kSectors, 0.0);
    cell_hits.assign(kRimCells + kSectors, 0);
    for (size_t k = 0; k < nt; ++k) {
      const V3 a = vertex(tri[3 * k]), b = vertex(tri[3 * k + 1]), c = vertex(tri[3 * k + 2]);
      const V3 n = cross(b - a, c - a);
      const double area = 0.5 * norm(n);
      const V3 m = (1.0 / 3.0) * (a + b + c);
      const double rm = std::sqrt(m.x * m.x + m.y * m.y);
      const double ang = std::atan2(m.y, m.x) + kPi;
      const int sec = std::min(kSectors - 1, static_cast<int>(ang / (2.0 * kPi) * kSectors));
      const bool rim_ground = ground_tri[k] && rm <= radius + kRimBandMm;
      const bool rim_wall = !ground_tri[k] && m.z > rim - kRimBandMm && m.z <= rim && rm <= radius + 1.0;
      if (area > 0.0 && (rim_ground || rim_wall)) {
        tri_rim[k] = static_cast<int16_t>(kRimCells + sec);
        cell_area[static_cast<size_t>(kRimCells + sec)] += area;
      }
      if (ground_tri[k]) continue;
      if (area <= 0.0 || std::fabs(n.z) > 0.7071 * 2.0 * area) continue;  // floor-like
      if (m.z > rim || rm > radius + 1.0) continue;  // outer wall
      const int band = std::clamp(static_cast<int>((m.z - zfloor) / depth * kBands), 0, kBands - 1);
      tri_cell[k] = static_cast<int16_t>(band * kSectors + sec);
      cell_area[static_cast<size_t>(band * kSectors + sec)] += area;
    }
  }

  bool in_dropout(V3 s) const {
    for (const DropoutPatch &d : patches) {
      const V3 e{s.x - d.x_mm, s.y - d.y_mm, s.z - d.z_mm};
      if (dot(e, e) < d.radius_mm * d.radius_mm) return true;
    }
    return false;
  }

  pv_point_t to_world(V3 q) const {
    pv_point_t o;
    o.x_mm = static_cast<float>(R[0] * q.x + R[1] * q.y + R[2] * q.z + t[0]);
    o.y_mm = static_cast<float>(R[3] * q.x + R[4] * q.y + R[5] * q.z + t[1]);
    o.z_mm = static_cast<float>(R[6] * q.x + R[7] * q.y + R[8] * q.z + t[2]);
    return o;
  }

  void init(const Pit &pit) {
    xyz = pit.scanned.xyz;
    tri = pit.scanned.tri;
    if (tri.size() % 3 != 0 || xyz.size() % 3 != 0)
      throw std::invalid_argument("handheld scan: malformed mesh");
    const size_t nv = xyz.size() / 3;
    for (uint32_t i : tri)
      if (i >= nv) throw std::invalid_argument("handheld scan: index out of range");

    rim = pit.rim_z_mm;
    zfloor = rim;
    double rmax = 0.0;
    for (size_t i = 0; i < nv; ++i) {
      const double x = xyz[3 * i], y = xyz[3 * i + 1], z = xyz[3 * i + 2];
      zfloor = std::min(zfloor, z);
      if (z < rim - 1e-3) rmax = std::max(rmax, std::sqrt(x * x + y * y));
    }
    depth = std::max(1.0, rim - zfloor);
    radius = pit.max_radius_mm > 0.0 ? pit.max_radius_mm : std::max(1.0, rmax);

    const double tol = 1e-3 * std::max(1.0, std::fabs(rim));
    const size_t nt = tri.size() / 3;
    const size_t ground_from = nt - std::min(nt, pit.ground_triangles);
    ground_tri.assign(nt, 0);
    for (size_t k = 0; k < nt; ++k) {
      bool flat = true;
      for (int c = 0; c < 3; ++c)
        flat = flat && std::fabs(xyz[3 * tri[3 * k + c] + 2] - rim) <= tol;
      ground_tri[k] = (flat || k >= ground_from) ? 1 : 0;  // the ring, even tilted
    }
    build_scene();
    build_cells();

    // Transform, from its own stream.
    Rng tr{derive_seed(p.transform_seed != 0 ? p.transform_seed : p.seed, 1)};
    tilt = tr.uniform(std::max(0.0, p.min_tilt_deg), std::max(0.0, p.max_tilt_deg));
    const double alpha = tr.uniform(0.0, 2.0 * kPi);
    const double yaw = tr.uniform(0.0, 2.0 * kPi);
    for (double &ti : t) ti = (tr.uniform() < 0.5 ? -1.0 : 1.0) * tr.uniform(100.0, 500.0);
    const double th = tilt * kPi / 180.0, ct = std::cos(th), st = std::sin(th);
    const double ax = std::cos(alpha), ay = std::sin(alpha);
    // Rodrigues about (ax, ay, 0).
    const double Ra[9] = {ct + (1 - ct) * ax * ax, (1 - ct) * ax * ay, st * ay,
                          (1 - ct) * ax * ay, ct + (1 - ct) * ay * ay, -st * ax,
                          -st * ay, st * ax, ct};
    const double cy = std::cos(yaw), sy = std::sin(yaw);
    const double Rz[9] = {cy, -sy, 0, sy, cy, 0, 0, 0, 1};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        double acc = 0.0;
        for (int m = 0; m < 3; ++m) acc += Ra[3 * i + m] * Rz[3 * m + k];
        R[3 * i + k] = acc;
      }

    // Stray box: 2-3 x the pit, around it.
    Rng sb{derive_seed(p.seed, 2)};
    const double f = sb.uniform(2.0, 3.0);
    const double zc = 0.5 * (zfloor + rim);
    box_lo = {-f * radius, -f * radius, zc - 0.5 * f * std::max(depth, radius)};
    box_hi = {f * radius, f * radius, zc + 0.5 * f * std::max(depth, radius)};

    draw_patches();
    path_rng = Rng{derive_seed(p.seed, 3)};
    noise_rng = Rng{derive_seed(p.seed, 4)};
    draw_pass();

    // Size the path: mean hits per frame over probe frames of pass 0.
    double hits = 0.0;
    for (int k = 0; k < kProbeFrames; ++k) {
      const double u = (k + 0.5) * kLoops / kProbeFrames;
      cast(pose(u), [&](V3, V3, double, double c, uint32_t) { hits += keep_probability(c); });
    }
    const double per_frame = hits / kProbeFrames;
    if (per_frame > 0.0) {
      const double frames = kPathMargin * p.target_points / per_frame;
      frames_per_loop = static_cast<uint64_t>(std::ceil(frames / kLoops));
    }
    frames_per_loop = std::clamp<uint64_t>(frames_per_loop, 24, 1000000);
    if (p.target_points == 0) done = true;
  }

  bool next(Frame *out) {
    out->points.clear();
    if (done) return false;
    out->points.reserve(static_cast<size_t>(p.rays_x) * p.rays_y / 2);
    if (frame_in_pass >= frames_per_loop * kLoops) {
      if (pass + 1 >= kMaxPasses) {
        done = true;
        return false;
      }
      ++pass;
      frame_in_pass = 0;
      draw_pass();
    }
    const double u = static_cast<double>(frame_in_pass) / static_cast<double>(frames_per_loop);
    const Pose ps = pose(u);
    out->sequence = static_cast<uint32_t>(frame_index);
    out->timestamp_us = p.frames_per_s > 0.0
        ? static_cast<uint64_t>(std::llround(static_cast<double>(frame_index) * 1e6 / p.frames_per_s))
        : 0;
    const double mp = std::max(0.0, p.multipath_share);
    const double sp = std::max(0.0, p.stray_share);
    const double sigma = std::max(0.0, p.noise_mm);
    cast(ps, [&](V3 s, V3 d, double thit, double cos_i, uint32_t pid) {
      if (!patches.empty() && in_dropout(s)) return;  // wet or dark soil
      // The pattern fades at grazing incidence: keep with keep_probability.
      if (noise_rng.uniform() >= keep_probability(cos_i)) return;
      if (tri_cell[pid] >= 0) ++cell_hits[static_cast<size_t>(tri_cell[pid])];
      if (tri_rim[pid] >= 0) ++cell_hits[static_cast<size_t>(tri_rim[pid])];
      const double r = noise_rng.uniform();
      V3 q;
      if (r < sp) {
        q = {noise_rng.uniform(box_lo.x, box_hi.x), noise_rng.uniform(box_lo.y, box_hi.y),
             noise_rng.uniform(box_lo.z, box_hi.z)};
      } else if (r < sp + mp) {
        // Floating point on the same ray, 2..40 mm in front of the hit; kept
        // below the rim plane for hits in the void, and in front of the scanner.
        double dist = noise_rng.uniform(2.0, 40.0);
        double dmax = 0.95 * thit;
        if (s.z < rim && d.z < 0.0) dmax = std::min(dmax, (rim - s.z) / -d.z);
        if (dist > 0.9 * dmax) dist = dmax * noise_rng.uniform(0.05, 0.9);
        q = s - dist * d;
      } else {
        q = sigma > 0.0 ? s + (sigma * noise_rng.gauss()) * d : s;
      }
      out->points.push_back(to_world(q));
    });
    ++frame_in_pass;
    ++frame_index;
    emitted += out->points.size();
    if (emitted >= p.target_points) done = true;
    return true;
  }
};

HandheldScan::HandheldScan(const Pit &pit, const ScanParams &p) : impl_(new Impl) {
  impl_->p = p;
  impl_->init(pit);
}

HandheldScan::~HandheldScan() = default;

bool HandheldScan::next(Frame *out) { return impl_->next(out); }

void HandheldScan::transform(double R[9], double t[3]) const {
  for (int i = 0; i < 9; ++i) R[i] = impl_->R[i];
  for (int i = 0; i < 3; ++i) t[i] = impl_->t[i];
}

double HandheldScan::tilt_deg() const { return impl_->tilt; }

const std::vector<DropoutPatch> &HandheldScan::dropout_patches() const {
  return impl_->patches;
}

WallCoverage wall_coverage_of(const std::vector<double> &area, const std::vector<uint32_t> &hits) {
  WallCoverage w;
  double total = 0.0, unseen = 0.0;
  constexpr size_t kWallCells = size_t(kCoverageSectors) * kCoverageBands;
  for (size_t i = kWallCells; i < area.size() && i < hits.size(); ++i) {
    if (area[i] <= 0.0) continue;
    ++w.rim_sectors;
    if (hits[i] < 3) ++w.rim_unseen_sectors;
  }
  for (size_t i = 0; i < kWallCells && i < area.size() && i < hits.size(); ++i) {
    if (area[i] <= 0.0) continue;
    ++w.cells;
    total += area[i];
    if (hits[i] < 3) {
      ++w.unseen_cells;
      unseen += area[i];
    }
  }
  w.unseen_share = total > 0.0 ? unseen / total : 0.0;
  return w;
}

WallCoverage HandheldScan::wall_coverage() const {
  return wall_coverage_of(impl_->cell_area, impl_->cell_hits);
}

void HandheldScan::wall_cells(std::vector<double> *area, std::vector<uint32_t> *hits) const {
  *area = impl_->cell_area;
  *hits = impl_->cell_hits;
}

}  // namespace pv::sim
