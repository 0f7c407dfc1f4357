// Procedural test pits with an exactly known void volume (see pit_geometry.h).
//
// Every family is a star-shaped wall r(theta, t) sampled on a grid of rings
// (one ring per nominal depth t, the same angles on every ring), closed at
// the bottom by a polar-grid floor (or, for the bowl, a single vertex) and at
// the top by a fan lid in the rim plane (or in the tilted ground plane, see
// PitOptions). The scanned mesh is the same wall
// and floor (same vertex indices) without the lid, plus the optional ground
// annulus whose inner boundary is the rim ring.
//
// Vertex layout (both meshes):
//   [0, NR*NA)             wall, ring k (bottom first) x angle j
//   [NR*NA, ...)           floor rings s = i/M, i = 1..M-1, then the floor
//                          centre (or the bowl's closing vertex)
//   void_closed:  + lid centre (last vertex)
//   scanned:      + ground rings (no lid centre)
//
// Ring xy coordinates are rounded to float with error diffusion on the ring
// polygon's area (the first-order area change of each rounding is tracked and
// the up/down choice that keeps the running sum near zero is taken), so the
// float mesh encloses the intended polygonal solid to ~1e-10 relative rather
// than ~1e-9.
#include "sim/pit_geometry.h"
#include "pitvol/splitmix64.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <stdexcept>
#include <utility>

namespace pv::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;

// splitmix64: the same draws on every platform and compiler.
struct Rng {
  uint64_t s;
  explicit Rng(uint64_t seed) : s(seed) {}
  uint64_t next() { return pv_splitmix64_next(&s); }
  double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  int integer(int lo, int hi) {  // inclusive
    return lo + static_cast<int>(next() % static_cast<uint64_t>(hi - lo + 1));
  }
};

uint64_t mix_seed(uint64_t seed, uint64_t stream) {
  Rng r(seed ^ (stream * 0xD1B54A32D192ED03ull));
  r.next();
  return r.next();
}

// Millimetre parameters are quantised to 1/1024 mm: exact in float and in
// the decimal params_json, so tests can rebuild closed forms bit-exactly.
double q(double x) { return std::round(x * 1024.0) / 1024.0; }

double smoothstep(double x) {
  x = std::min(1.0, std::max(0.0, x));
  return x * x * (3.0 - 2.0 * x);
}

// 1 on [-hw, hw] with smoothstep edges of width tw centred on +-hw.
double smooth_box(double u, double hw, double tw) {
  return smoothstep((u + hw + 0.5 * tw) / tw) * smoothstep((hw + 0.5 * tw - u) / tw);
}

// Raised cosine: 1 at 0, 0 at |u| >= hw.
double raised_cos(double u, double hw) {
  if (std::fabs(u) >= hw) return 0.0;
  return 0.5 * (1.0 + std::cos(kPi * u / hw));
}

double wrap_pi(double a) {
  a = std::fmod(a, kTwoPi);
  if (a > kPi) a -= kTwoPi;
  if (a <= -kPi) a += kTwoPi;
  return a;
}

struct Interval {
  double a, b;
};

// Levels from lo to hi inclusive: uniform steps of `step`, `fine` inside the
// refine intervals. Each segment between breakpoints is split uniformly.
std::vector<double> build_levels(double lo, double hi, double step, double fine,
                                 std::vector<Interval> refine) {
  for (auto &iv : refine) {
    iv.a = std::max(lo, iv.a);
    iv.b = std::min(hi, iv.b);
  }
  refine.erase(std::remove_if(refine.begin(), refine.end(),
                              [](const Interval &iv) { return iv.b <= iv.a; }),
               refine.end());
  std::sort(refine.begin(), refine.end(),
            [](const Interval &x, const Interval &y) { return x.a < y.a; });
  std::vector<Interval> merged;
  for (const auto &iv : refine) {
    if (!merged.empty() && iv.a <= merged.back().b)
      merged.back().b = std::max(merged.back().b, iv.b);
    else
      merged.push_back(iv);
  }
  // Segments: (start, end, is_fine).
  std::vector<std::pair<Interval, bool>> segs;
  double cur = lo;
  for (const auto &iv : merged) {
    if (iv.a > cur) segs.push_back({{cur, iv.a}, false});
    segs.push_back({{iv.a, iv.b}, true});
    cur = iv.b;
  }
  if (hi > cur) segs.push_back({{cur, hi}, false});
  std::vector<double> out;
  out.push_back(lo);
  for (const auto &sg : segs) {
    const double len = sg.first.b - sg.first.a;
    const double st = sg.second ? fine : step;
    const int n = std::max(1, static_cast<int>(std::ceil(len / st - 1e-9)));
    for (int i = 1; i <= n; ++i)
      out.push_back(i == n ? sg.first.b : sg.first.a + len * i / n);
  }
  return out;
}

// Angles in [0, 2 pi): 2 pi / n_base steps, `fine` inside refine intervals
// (given as centre +- half width, wrapping around).
std::vector<double> build_angles(int n_base, double fine, const std::vector<Interval> &around) {
  std::vector<Interval> ref;
  for (const auto &iv : around) {
    double a = iv.a, b = iv.b;
    if (a < 0.0) {
      ref.push_back({a + kTwoPi, kTwoPi});
      a = 0.0;
    }
    if (b > kTwoPi) {
      ref.push_back({0.0, b - kTwoPi});
      b = kTwoPi;
    }
    ref.push_back({a, b});
  }
  std::vector<double> th = build_levels(0.0, kTwoPi, kTwoPi / n_base, fine, ref);
  th.pop_back();  // 2 pi == 0
  return th;
}

class Json {
 public:
  void str(const char *k, const std::string &v) { key(k); s_ += "\"" + v + "\""; }
  void num(const char *k, double v) {
    key(k);
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    s_ += buf;
  }
  void integer(const char *k, long long v) {
    key(k);
    s_ += std::to_string(v);
  }
  void boolean(const char *k, bool v) { key(k); s_ += v ? "true" : "false"; }
  void raw(const char *k, const std::string &v) { key(k); s_ += v; }
  std::string done() const { return "{" + s_ + "}"; }

 private:
  void key(const char *k) {
    if (!s_.empty()) s_ += ",";
    s_ += "\"";
    s_ += k;
    s_ += "\":";
  }
  std::string s_;
};

std::string num_array(const std::vector<double> &v) {
  std::string s = "[";
  char buf[40];
  for (size_t i = 0; i < v.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%s%.17g", i ? "," : "", v[i]);
    s += buf;
  }
  return s + "]";
}

// [{"k0":v,"k1":v,...},...]: one object per row, the keys in order.
std::string object_array(const std::vector<const char *> &keys,
                         const std::vector<std::vector<double>> &rows) {
  std::string s = "[";
  char buf[48];
  for (size_t i = 0; i < rows.size(); ++i) {
    s += i ? ",{" : "{";
    for (size_t k = 0; k < keys.size() && k < rows[i].size(); ++k) {
      std::snprintf(buf, sizeof buf, "%.17g", rows[i][k]);
      s += std::string(k ? ",\"" : "\"") + keys[k] + "\":" + buf;
    }
    s += "}";
  }
  return s + "]";
}

// What a family hands to the mesh builder.
struct Shape {
  std::vector<double> theta;  // ring angles, increasing in [0, 2 pi)
  std::vector<double> t;      // ring parameters (nominal z), bottom first, back() = h
  std::function<double(double theta, double t)> radius;
  // Floor height offset at polar-grid point (x, y) = s r_bottom(theta) (cos, sin);
  // empty = flat. Must not depend on theta at s = 0.
  std::function<double(double x, double y, double s, double theta)> floor;
  double floor_blend_mm = 30.0;  // wall z offset fades out over this height
  bool closing_vertex = false;   // bowl: the bottom ring closes at (0, 0, 0)
  double h = 0.0;
  double ring_step_mm = 1.0;
  Json params;
};

// Round a closed ring polygon's xy to float with error diffusion on its area.
void round_ring(const std::vector<double> &px, const std::vector<double> &py, float *ox,
                float *oy, size_t stride) {
  const size_t n = px.size();
  double acc = 0.0;
  for (size_t j = 0; j < n; ++j) {
    const size_t jp = (j + 1) % n, jm = (j + n - 1) % n;
    const double gx = 0.5 * (py[jp] - py[jm]);
    const double gy = 0.5 * (px[jm] - px[jp]);
    float cx[2], cy[2];
    int nx = 1, ny = 1;
    cx[0] = static_cast<float>(px[j]);
    cy[0] = static_cast<float>(py[j]);
    if (static_cast<double>(cx[0]) != px[j]) {
      cx[1] = std::nextafter(cx[0], static_cast<double>(cx[0]) > px[j]
                                        ? -std::numeric_limits<float>::infinity()
                                        : std::numeric_limits<float>::infinity());
      nx = 2;
    }
    if (static_cast<double>(cy[0]) != py[j]) {
      cy[1] = std::nextafter(cy[0], static_cast<double>(cy[0]) > py[j]
                                        ? -std::numeric_limits<float>::infinity()
                                        : std::numeric_limits<float>::infinity());
      ny = 2;
    }
    double best = std::numeric_limits<double>::infinity(), best_d = 0.0;
    int bx = 0, by = 0;
    for (int a = 0; a < nx; ++a)
      for (int b = 0; b < ny; ++b) {
        const double d = gx * (static_cast<double>(cx[a]) - px[j]) +
                         gy * (static_cast<double>(cy[b]) - py[j]);
        if (std::fabs(acc + d) < best) {
          best = std::fabs(acc + d);
          best_d = d;
          bx = a;
          by = b;
        }
      }
    acc += best_d;
    ox[j * stride] = cx[bx];
    oy[j * stride] = cy[by];
  }
}

void push_vertex(std::vector<float> &xyz, double x, double y, double z) {
  xyz.push_back(static_cast<float>(x));
  xyz.push_back(static_cast<float>(y));
  xyz.push_back(static_cast<float>(z));
}

void push_tri(std::vector<uint32_t> &t, size_t a, size_t b, size_t c) {
  t.push_back(static_cast<uint32_t>(a));
  t.push_back(static_cast<uint32_t>(b));
  t.push_back(static_cast<uint32_t>(c));
}

// Quads between an inner and an outer ring of a horizontal-ish annulus, facing
// down (clockwise seen from above).
void annulus_down(std::vector<uint32_t> &tri, const std::function<size_t(size_t)> &in,
                  const std::function<size_t(size_t)> &out, size_t na) {
  for (size_t j = 0; j < na; ++j) {
    const size_t jn = (j + 1) % na;
    push_tri(tri, in(j), in(jn), out(jn));
    push_tri(tri, in(j), out(jn), out(j));
  }
}

// Height of the tilted ground plane above the rim height at (x, y).
struct GroundPlane {
  double gx = 0.0, gy = 0.0;
  bool tilted = false;
  explicit GroundPlane(const PitOptions &o) {
    if (o.ground_tilt_deg == 0.0) return;
    const double s = std::tan(o.ground_tilt_deg * kPi / 180.0);
    gx = s * std::cos(o.ground_tilt_azimuth_rad);
    gy = s * std::sin(o.ground_tilt_azimuth_rad);
    tilted = true;
  }
  double at(double x, double y) const { return gx * x + gy * y; }
};

Pit build(const Shape &S, Family fam, bool ground, uint64_t seed, const PitOptions &opt,
          const std::vector<PitOptions::Bump> &bumps) {
  Pit pit{};
  pit.family = fam;
  pit.ground = ground;
  pit.seed = seed;
  pit.surround = ground ? "ground" : "none";
  const size_t na = S.theta.size(), nr = S.t.size();
  const float hf = static_cast<float>(S.h);
  pit.rim_z_mm = static_cast<double>(hf);

  std::vector<double> cs(na), sn(na), edge(na, 0.0);
  for (size_t j = 0; j < na; ++j) {
    cs[j] = std::cos(S.theta[j]);
    sn[j] = std::sin(S.theta[j]);
  }
  // Exact bottom ring radius (the floor is built from it).
  const double t0 = static_cast<double>(static_cast<float>(S.t[0]));
  std::vector<double> rb(na);
  for (size_t j = 0; j < na; ++j) rb[j] = S.radius(S.theta[j], t0);
  if (S.floor)
    for (size_t j = 0; j < na; ++j)
      edge[j] = S.floor(rb[j] * cs[j], rb[j] * sn[j], 1.0, S.theta[j]);
  for (const PitOptions::Bump &b : bumps) {
    // A stone must lie on a floor grid and clear the wall.
    const double reach = std::hypot(b.x_mm, b.y_mm) + b.radius_mm + 2.0;
    if (S.closing_vertex || b.height_mm < 0.0 || b.radius_mm <= 0.0 ||
        reach > *std::min_element(rb.begin(), rb.end()))
      throw std::invalid_argument("make_pit: the stone must sit on a flat floor, clear of the wall");
  }
  if (opt.container_lip_mm > 0.0 && (ground || opt.ground_tilt_deg != 0.0))
    throw std::invalid_argument("make_pit: a container has neither ground nor a tilted ground plane");
  const GroundPlane plane(opt);

  Mesh &v = pit.void_closed;
  v.xyz.resize(3 * na * nr);
  std::vector<double> px(na), py(na);
  double max_r = 0.0, max_rim_r = 0.0, min_rim_r = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < nr; ++k) {
    const float tf = static_cast<float>(S.t[k]);
    const double td = static_cast<double>(tf);
    for (size_t j = 0; j < na; ++j) {
      const double r = k == 0 ? rb[j] : S.radius(S.theta[j], td);
      px[j] = r * cs[j];
      py[j] = r * sn[j];
      const double blend = std::max(0.0, 1.0 - td / S.floor_blend_mm);
      v.xyz[3 * (k * na + j) + 2] =
          (edge[j] != 0.0 && blend > 0.0) ? static_cast<float>(td + edge[j] * blend) : tf;
    }
    round_ring(px, py, &v.xyz[3 * k * na], &v.xyz[3 * k * na + 1], 3);
    if (plane.tilted) {
      // Shear in z: 0 at the floor, the whole plane offset at the rim.
      const double share = td / static_cast<double>(hf);
      for (size_t j = 0; j < na; ++j) {
        float *q = &v.xyz[3 * (k * na + j)];
        const double blend = std::max(0.0, 1.0 - td / S.floor_blend_mm);
        const double z0 = (edge[j] != 0.0 && blend > 0.0) ? td + edge[j] * blend : td;
        q[2] = static_cast<float>(z0 + share * plane.at(static_cast<double>(q[0]),
                                                        static_cast<double>(q[1])));
      }
    }
    for (size_t j = 0; j < na; ++j) {
      const double r = std::hypot(static_cast<double>(v.xyz[3 * (k * na + j)]),
                                  static_cast<double>(v.xyz[3 * (k * na + j) + 1]));
      max_r = std::max(max_r, r);
      if (k + 1 == nr) {
        max_rim_r = std::max(max_rim_r, r);
        min_rim_r = std::min(min_rim_r, r);
      }
    }
  }
  auto W = [na](size_t k, size_t j) { return k * na + j; };
  for (size_t k = 0; k + 1 < nr; ++k)
    for (size_t j = 0; j < na; ++j) {
      const size_t jn = (j + 1) % na;
      push_tri(v.tri, W(k, j), W(k, jn), W(k + 1, jn));
      push_tri(v.tri, W(k, j), W(k + 1, jn), W(k + 1, j));
    }

  // Floor.
  const size_t floor_base = na * nr;
  if (S.closing_vertex) {
    push_vertex(v.xyz, 0.0, 0.0, 0.0);
    for (size_t j = 0; j < na; ++j) push_tri(v.tri, floor_base, W(0, (j + 1) % na), W(0, j));
  } else {
    double rbmax = 0.0;
    for (double r : rb) rbmax = std::max(rbmax, r);
    const size_t M = std::max<size_t>(2, static_cast<size_t>(std::ceil(rbmax / 2.0)));
    for (size_t i = 1; i < M; ++i) {
      const double s = static_cast<double>(i) / static_cast<double>(M);
      for (size_t j = 0; j < na; ++j) {
        const double x = s * rb[j] * cs[j], y = s * rb[j] * sn[j];
        push_vertex(v.xyz, x, y, t0 + (S.floor ? S.floor(x, y, s, S.theta[j]) : 0.0));
      }
    }
    const size_t centre = floor_base + (M - 1) * na;
    push_vertex(v.xyz, 0.0, 0.0, t0 + (S.floor ? S.floor(0.0, 0.0, 0.0, 0.0) : 0.0));
    auto F = [&](size_t i, size_t j) { return i == M ? W(0, j) : floor_base + (i - 1) * na + j; };
    for (size_t j = 0; j < na; ++j) push_tri(v.tri, centre, F(1, (j + 1) % na), F(1, j));
    for (size_t i = 1; i < M; ++i)
      annulus_down(v.tri, [&](size_t j) { return F(i, j); }, [&](size_t j) { return F(i + 1, j); },
                   na);
  }

  // Scanned = wall + floor (same indices), before the lid is added.
  pit.scanned.xyz = v.xyz;
  pit.scanned.tri = v.tri;

  // Lid: fan about the axis in the rim plane, facing up.
  const size_t lid = v.vertices();
  push_vertex(v.xyz, 0.0, 0.0, pit.rim_z_mm);
  for (size_t j = 0; j < na; ++j) push_tri(v.tri, lid, W(nr - 1, j), W(nr - 1, (j + 1) % na));

  // Ground annulus: from the rim ring to a circle, facing down (into the soil,
  // consistent with the wall across the rim edge).
  Rng grng(mix_seed(seed, 0x67726F756E64ull + static_cast<uint64_t>(fam)));
  const double ground_w =
      opt.ground_width_mm > 0.0 ? q(opt.ground_width_mm) : q(grng.uniform(40.0, 80.0));
  if (ground) {
    Mesh &sc = pit.scanned;
    const double rg = q(max_rim_r + ground_w);
    pit.ground_outer_radius_mm = rg;
    const size_t mg =
        std::max<size_t>(1, static_cast<size_t>(std::ceil((rg - min_rim_r) / 2.5)));
    const size_t gbase = sc.vertices();
    std::vector<double> ox(na), oy(na);
    for (size_t j = 0; j < na; ++j) {
      ox[j] = rg * cs[j];
      oy[j] = rg * sn[j];
    }
    for (size_t i = 1; i <= mg; ++i) {
      const double s = static_cast<double>(i) / static_cast<double>(mg);
      for (size_t j = 0; j < na; ++j) {
        const double rx = static_cast<double>(v.xyz[3 * W(nr - 1, j)]);
        const double ry = static_cast<double>(v.xyz[3 * W(nr - 1, j) + 1]);
        const double x = i == mg ? ox[j] : rx + s * (ox[j] - rx);
        const double y = i == mg ? oy[j] : ry + s * (oy[j] - ry);
        const double z =
            plane.tilted ? pit.rim_z_mm + plane.at(static_cast<double>(static_cast<float>(x)),
                                                   static_cast<double>(static_cast<float>(y)))
                         : pit.rim_z_mm;
        push_vertex(sc.xyz, x, y, z);
      }
    }
    auto G = [&](size_t i, size_t j) { return i == 0 ? W(nr - 1, j) : gbase + (i - 1) * na + j; };
    for (size_t i = 0; i < mg; ++i)
      annulus_down(sc.tri, [&](size_t j) { return G(i, j); }, [&](size_t j) { return G(i + 1, j); },
                   na);
    pit.ground_triangles = 2 * na * mg;
  }

  // Container: the outer wall (facing out, so that rays from outside meet
  // its front), then the lip (last: the flat triangles the scan sees from
  // above, like a ground ring). The outer wall stands the lip's width
  // outside the widest ring at each angle (a bulge, an undercut, a groove),
  // as a real vessel's wall does: the pit's surface never pokes through it.
  if (opt.container_lip_mm > 0.0) {
    Mesh &sc = pit.scanned;
    const double w = opt.container_lip_mm;
    const double wall_h = opt.container_wall_mm > 0.0 ? opt.container_wall_mm : pit.rim_z_mm;
    const size_t top = sc.vertices(), bottom = top + na;
    std::vector<double> lx(na), ly(na);
    for (size_t j = 0; j < na; ++j) {
      const double rx = static_cast<double>(v.xyz[3 * W(nr - 1, j)]);
      const double ry = static_cast<double>(v.xyz[3 * W(nr - 1, j) + 1]);
      const double r = std::hypot(rx, ry);
      double widest = r;
      for (size_t k = 0; k + 1 < nr; ++k)
        widest = std::max(widest, std::hypot(static_cast<double>(v.xyz[3 * W(k, j)]),
                                             static_cast<double>(v.xyz[3 * W(k, j) + 1])));
      lx[j] = rx * (widest + w) / r;
      ly[j] = ry * (widest + w) / r;
      pit.lip_outer_radius_mm = std::max(pit.lip_outer_radius_mm, widest + w);
    }
    for (size_t j = 0; j < na; ++j) push_vertex(sc.xyz, lx[j], ly[j], pit.rim_z_mm);
    for (size_t j = 0; j < na; ++j) push_vertex(sc.xyz, lx[j], ly[j], pit.rim_z_mm - wall_h);
    for (size_t j = 0; j < na; ++j) {
      const size_t jn = (j + 1) % na;
      push_tri(sc.tri, bottom + j, top + jn, bottom + jn);
      push_tri(sc.tri, bottom + j, top + j, top + jn);
    }
    annulus_down(sc.tri, [&](size_t j) { return W(nr - 1, j); }, [&](size_t j) { return top + j; },
                 na);
    pit.ground_triangles = 2 * na;
    pit.surround = "container";
  }

  pit.max_radius_mm = max_r;
  pit.volume_mm3 = signed_volume_mm3(v);

  Json js;
  js.str("family", family_name(fam));
  js.integer("seed", static_cast<long long>(seed));
  js.boolean("ground", ground);
  js.num("depth_mm", pit.rim_z_mm);
  js.integer("angles", static_cast<long long>(na));
  js.integer("rings", static_cast<long long>(nr));
  js.num("ring_step_mm", S.ring_step_mm);
  const std::string fam_params = S.params.done();
  std::string out = js.done();
  if (fam_params.size() > 2) out = out.substr(0, out.size() - 1) + "," + fam_params.substr(1);
  if (ground) {
    out = out.substr(0, out.size() - 1);
    char buf[128];
    std::snprintf(buf, sizeof buf, ",\"ground_width_mm\":%.17g,\"ground_outer_radius_mm\":%.17g}",
                  ground_w, pit.ground_outer_radius_mm);
    out += buf;
  }
  // Stress options, only when used (the standard pits' JSON is unchanged).
  Json extra;
  if (opt.depth_mm > 0.0) extra.boolean("depth_override", true);
  if (plane.tilted) {
    extra.num("ground_tilt_deg", opt.ground_tilt_deg);
    extra.num("ground_tilt_azimuth_rad", opt.ground_tilt_azimuth_rad);
    extra.str("lid", "tilted ground plane");
  }
  if (opt.scale_xy != 1.0 || opt.scale_z != 1.0) {
    extra.num("scale_xy", opt.scale_xy);
    extra.num("scale_z", opt.scale_z);
  }
  if (opt.ground_width_mm > 0.0) extra.boolean("ground_width_override", true);
  if (opt.container_lip_mm > 0.0) {
    extra.str("surround", "container");
    extra.num("lip_mm", opt.container_lip_mm);
    extra.num("lip_outer_radius_mm", pit.lip_outer_radius_mm);
    extra.num("outer_wall_mm",
              opt.container_wall_mm > 0.0 ? opt.container_wall_mm : pit.rim_z_mm);
  }
  if (!opt.lumps.empty()) {
    double lv = 0.0;
    std::vector<std::vector<double>> rows;
    for (const PitOptions::Bump &b : opt.lumps) {
      rows.push_back({b.height_mm, b.radius_mm, b.x_mm, b.y_mm});
      lv += stone_volume_mm3(b.height_mm, b.radius_mm);
    }
    extra.raw("lumps", object_array({"height_mm", "radius_mm", "x_mm", "y_mm"}, rows));
    extra.num("lumps_volume_mm3", lv);
  }
  if (!opt.grooves.empty()) {
    std::vector<std::vector<double>> rows;
    for (const PitOptions::Groove &g : opt.grooves)
      rows.push_back({g.z_mm, g.width_mm, g.depth_mm, g.tilt_mm});
    extra.raw("grooves", object_array({"z_mm", "width_mm", "depth_mm", "tilt_mm"}, rows));
  }
  if (opt.stone_height_mm != 0.0) {
    extra.num("stone_height_mm", opt.stone_height_mm);
    extra.num("stone_radius_mm", opt.stone_radius_mm);
    extra.num("stone_x_mm", opt.stone_x_mm);
    extra.num("stone_y_mm", opt.stone_y_mm);
    extra.num("stone_volume_mm3", stone_volume_mm3(opt.stone_height_mm, opt.stone_radius_mm));
  }
  const std::string ex = extra.done();
  if (ex.size() > 2) out = out.substr(0, out.size() - 1) + "," + ex.substr(1);
  pit.params_json = out;
  return pit;
}

// ---------------------------------------------------------------------------
// Families.

Shape cylinder_like(Rng &rng, double r_lo, double r_hi, double h_lo, double h_hi, int angles,
                    double step) {
  Shape S;
  const double R = q(rng.uniform(r_lo, r_hi));
  S.h = q(rng.uniform(h_lo, h_hi));
  S.ring_step_mm = step;
  S.theta = build_angles(angles, 0.0, {});
  S.t = build_levels(0.0, S.h, step, step, {});
  S.radius = [R](double, double) { return R; };
  S.params.num("radius_mm", R);
  return S;
}

Shape protrusions(Rng &rng) {
  Shape S;
  const double R = q(rng.uniform(105.0, 115.0));
  S.h = q(rng.uniform(280.0, 300.0));
  S.ring_step_mm = 1.0;
  const double tw = 2.0;  // smoothstep width of the block sides, mm
  struct Block {
    double th, hw_arc, zc, hh, d;
  };
  std::vector<Block> blocks;
  const int n = rng.integer(4, 8);
  for (int tries = 0; static_cast<int>(blocks.size()) < n && tries < 1000; ++tries) {
    Block b;
    b.th = rng.uniform(0.0, kTwoPi);
    b.hw_arc = q(rng.uniform(20.0, 60.0)) / 2.0;
    b.hh = q(rng.uniform(20.0, 80.0)) / 2.0;
    b.zc = q(rng.uniform(15.0 + b.hh, S.h - 15.0 - b.hh));
    b.d = q(rng.uniform(10.0, 30.0));
    bool clash = false;
    for (const auto &o : blocks)
      if (std::fabs(wrap_pi(b.th - o.th)) * R < b.hw_arc + o.hw_arc + 3.0 * tw &&
          std::fabs(b.zc - o.zc) < b.hh + o.hh + 3.0 * tw)
        clash = true;
    if (!clash) blocks.push_back(b);
  }
  std::vector<Interval> th_ref, z_ref;
  for (const auto &b : blocks) {
    const double dth = b.hw_arc / R, m = tw / R;
    th_ref.push_back({b.th - dth - m, b.th - dth + m});
    th_ref.push_back({b.th + dth - m, b.th + dth + m});
    z_ref.push_back({b.zc - b.hh - tw, b.zc - b.hh + tw});
    z_ref.push_back({b.zc + b.hh - tw, b.zc + b.hh + tw});
  }
  S.theta = build_angles(720, 0.25 / R, th_ref);
  S.t = build_levels(0.0, S.h, 1.0, 0.25, z_ref);
  S.radius = [R, blocks, tw](double th, double z) {
    double p = 0.0;
    for (const auto &b : blocks) {
      const double wz = smooth_box(z - b.zc, b.hh, tw);
      if (wz == 0.0) continue;
      p = std::max(p, b.d * wz * smooth_box(wrap_pi(th - b.th) * R, b.hw_arc, tw));
    }
    return R - p;
  };
  S.params.num("radius_mm", R);
  S.params.num("side_transition_mm", tw);
  std::string arr = "[";
  for (size_t i = 0; i < blocks.size(); ++i) {
    const auto &b = blocks[i];
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "%s{\"theta_rad\":%.17g,\"arc_mm\":%.17g,\"z_centre_mm\":%.17g,"
                  "\"height_mm\":%.17g,\"protrusion_mm\":%.17g}",
                  i ? "," : "", b.th, 2.0 * b.hw_arc, b.zc, 2.0 * b.hh, b.d);
    arr += buf;
  }
  S.params.raw("blocks", arr + "]");
  return S;
}

Shape textured(Rng &rng) {
  Shape S;
  const double R = q(rng.uniform(105.0, 115.0));
  S.h = q(rng.uniform(280.0, 300.0));
  const double lining = 5.0;
  S.ring_step_mm = 0.5;
  struct Groove {
    double z, w, d, tilt, phase;
  };
  std::vector<Groove> gr;
  for (double z = rng.uniform(8.0, 25.0); z < S.h - 8.0; z += rng.uniform(15.0, 30.0)) {
    Groove g;
    g.z = z;
    g.w = rng.uniform(3.0, 6.0);
    g.d = rng.uniform(2.0, 4.0);
    g.tilt = rng.uniform(0.0, 3.0);
    g.phase = rng.uniform(0.0, kTwoPi);
    gr.push_back(g);
  }
  struct Wave {
    double m, kz, phase;
  };
  const int n_waves = 24;
  const double rough_rms = 0.5;
  const double amp = rough_rms / std::sqrt(0.5 * n_waves);
  std::vector<Wave> waves;
  const int m_lo = static_cast<int>(std::round(kTwoPi * R / 30.0));
  const int m_hi = static_cast<int>(std::round(kTwoPi * R / 6.0));
  for (int i = 0; i < n_waves; ++i) {
    Wave w;
    w.m = rng.integer(m_lo, m_hi);
    w.kz = (rng.uniform() < 0.5 ? -1.0 : 1.0) * kTwoPi / rng.uniform(6.0, 30.0);
    w.phase = rng.uniform(0.0, kTwoPi);
    waves.push_back(w);
  }
  S.theta = build_angles(720, 0.0, {});
  S.t = build_levels(0.0, S.h, 0.5, 0.5, {});
  const double base = R - lining;
  S.radius = [base, gr, waves, amp](double th, double z) {
    double r = base;
    for (const auto &g : gr) {
      const double u = z - (g.z + g.tilt * std::sin(th - g.phase));
      if (std::fabs(u) < 0.5 * g.w) r += g.d * 0.5 * (1.0 + std::cos(kTwoPi * u / g.w));
    }
    for (const auto &w : waves) r += amp * std::cos(w.m * th + w.kz * z + w.phase);
    return r;
  };
  S.params.num("radius_mm", R);
  S.params.num("lining_mm", lining);
  S.params.num("roughness_rms_mm", rough_rms);
  std::vector<double> gz, gw, gd;
  for (const auto &g : gr) {
    gz.push_back(g.z);
    gw.push_back(g.w);
    gd.push_back(g.d);
  }
  S.params.raw("groove_z_mm", num_array(gz));
  S.params.raw("groove_width_mm", num_array(gw));
  S.params.raw("groove_depth_mm", num_array(gd));
  return S;
}

Shape tapered(Rng &rng) {
  Shape S;
  const double rb = q(rng.uniform(80.0, 100.0));
  const double rt = q(rng.uniform(120.0, 140.0));
  S.h = q(rng.uniform(280.0, 300.0));
  S.theta = build_angles(720, 0.0, {});
  S.t = build_levels(0.0, S.h, 1.0, 1.0, {});
  const double h = S.h;
  S.radius = [rb, rt, h](double, double z) { return rb + (rt - rb) * (z / h); };
  S.params.num("r_bottom_mm", rb);
  S.params.num("r_top_mm", rt);
  return S;
}

// A half-ellipsoid cap (semi-axes R across, c down) under a vertical wall
// up to h, closing at one vertex; the cap's rings about 1 mm of arc apart.
Shape capped(double R, double h, double c) {
  Shape S;
  S.h = h;
  S.closing_vertex = true;
  S.theta = build_angles(720, 0.0, {});
  const int ncap = static_cast<int>(std::ceil(0.5 * kPi * std::max(R, c)));  // ~1 mm of arc
  for (int i = 1; i < ncap; ++i) S.t.push_back(c * (1.0 - std::cos(0.5 * kPi * i / ncap)));
  for (double z : build_levels(c, S.h, 1.0, 1.0, {})) S.t.push_back(z);
  S.radius = [R, c](double, double z) {
    if (z >= c) return R;
    const double u = 1.0 - z / c;
    return R * std::sqrt(std::max(0.0, 1.0 - u * u));
  };
  S.params.num("radius_mm", R);
  S.params.num("cap_height_mm", c);
  S.params.integer("cap_rings", ncap);
  return S;
}

Shape bowl(Rng &rng) {
  const double R = q(rng.uniform(105.0, 115.0));
  const double h = q(rng.uniform(280.0, 300.0));
  const double c = q(rng.uniform(40.0, 80.0));
  return capped(R, h, c);
}

// A fully rounded bowl: the cap is nearly all of the pit, under a short
// wall (5-25 % of the depth); no flat floor anywhere.
Shape rounded_bowl(Rng &rng) {
  const double R = q(rng.uniform(105.0, 115.0));
  const double h = q(rng.uniform(150.0, 250.0));
  const double wall = q(h * rng.uniform(0.05, 0.25));
  Shape S = capped(R, h, h - wall);
  S.params.num("wall_mm", wall);
  return S;
}

Shape necking(Rng &rng) {
  Shape S;
  const double R = q(rng.uniform(105.0, 115.0));
  S.h = q(rng.uniform(280.0, 300.0));
  const double a = q(rng.uniform(15.0, 30.0));
  const double zc = q(S.h * rng.uniform(0.4, 0.6));
  const double w = q(rng.uniform(30.0, 60.0));
  S.theta = build_angles(720, 0.0, {});
  S.t = build_levels(0.0, S.h, 1.0, 1.0, {});
  S.radius = [R, a, zc, w](double, double z) {
    const double u = (z - zc) / w;
    return R - a * std::exp(-u * u);
  };
  S.params.num("radius_mm", R);
  S.params.num("neck_amp_mm", a);
  S.params.num("neck_z_mm", zc);
  S.params.num("neck_width_mm", w);
  return S;
}

Shape bulge(Rng &rng) {
  Shape S;
  const double R = q(rng.uniform(105.0, 115.0));
  S.h = q(rng.uniform(280.0, 300.0));
  const double b = q(rng.uniform(15.0, 30.0));
  const double width = q(rng.uniform(60.0, 120.0));
  const double height = q(rng.uniform(60.0, 120.0));
  const double thc = rng.uniform(0.0, kTwoPi);
  const double zc = q(rng.uniform(20.0 + 0.5 * height, S.h - 20.0 - 0.5 * height));
  S.theta = build_angles(720, 0.0, {});
  S.t = build_levels(0.0, S.h, 1.0, 1.0, {});
  S.radius = [=](double th, double z) {
    return R + b * raised_cos(wrap_pi(th - thc) * R, 0.5 * width) * raised_cos(z - zc, 0.5 * height);
  };
  S.params.num("radius_mm", R);
  S.params.num("bulge_amp_mm", b);
  S.params.num("bulge_width_mm", width);
  S.params.num("bulge_height_mm", height);
  S.params.num("bulge_theta_rad", thc);
  S.params.num("bulge_z_mm", zc);
  return S;
}

Shape elliptical(Rng &rng) {
  Shape S;
  const double a = q(rng.uniform(120.0, 140.0));
  const double b = q(rng.uniform(80.0, 100.0));
  const double phi = rng.uniform(0.0, kPi);
  S.h = q(rng.uniform(280.0, 300.0));
  S.theta = build_angles(720, 0.0, {});
  S.t = build_levels(0.0, S.h, 1.0, 1.0, {});
  S.radius = [a, b, phi](double th, double) {
    const double c = std::cos(th - phi), s = std::sin(th - phi);
    return a * b / std::sqrt(b * b * c * c + a * a * s * s);
  };
  S.params.num("a_mm", a);
  S.params.num("b_mm", b);
  S.params.num("orientation_rad", phi);
  return S;
}

Shape hand_dug(Rng &rng) {
  Shape S;
  const double R = q(rng.uniform(100.0, 120.0));
  S.h = q(rng.uniform(260.0, 300.0));
  struct Harm {
    double k, a, phase, twist;
  };
  std::vector<Harm> hs;
  for (int k = 2; k <= 5; ++k)
    hs.push_back({static_cast<double>(k), rng.uniform(0.005, 0.015), rng.uniform(0.0, kTwoPi),
                  rng.uniform(-1.5, 1.5)});
  const double za = rng.uniform(0.005, 0.02), zl = rng.uniform(100.0, 300.0),
               zp = rng.uniform(0.0, kTwoPi);
  // Floor: tilt, saddle and three bumps; a few mm of relief.
  const double t1 = rng.uniform(1.0, 4.0), a1 = rng.uniform(0.0, kTwoPi);
  const double t2 = rng.uniform(0.5, 2.0), a2 = rng.uniform(0.0, kTwoPi);
  struct Bump {
    double x, y, amp, sig;
  };
  std::vector<Bump> bumps;
  for (int i = 0; i < 3; ++i) {
    const double rr = 0.6 * R * std::sqrt(rng.uniform()), ang = rng.uniform(0.0, kTwoPi);
    bumps.push_back({rr * std::cos(ang), rr * std::sin(ang), rng.uniform(-3.0, 3.0),
                     rng.uniform(15.0, 40.0)});
  }
  const double h = S.h;
  S.theta = build_angles(720, 0.0, {});
  S.t = build_levels(0.0, S.h, 1.0, 1.0, {});
  S.radius = [=](double th, double z) {
    double f = 1.0 + za * std::sin(kTwoPi * z / zl + zp);
    for (const auto &hm : hs) f += hm.a * std::cos(hm.k * th + hm.phase + hm.twist * z / h);
    return R * f;
  };
  S.floor = [=](double x, double y, double s, double th) {
    double f = t1 * s * std::cos(th - a1) + t2 * s * s * std::cos(2.0 * th - a2);
    for (const auto &b : bumps) {
      const double dx = x - b.x, dy = y - b.y;
      f += b.amp * std::exp(-(dx * dx + dy * dy) / (2.0 * b.sig * b.sig));
    }
    return f;
  };
  S.params.num("radius_mm", R);
  std::vector<double> ha;
  for (const auto &hm : hs) ha.push_back(hm.a);
  S.params.raw("harmonic_amp_k2_to_k5", num_array(ha));
  S.params.num("depth_wave_amp", za);
  S.params.num("depth_wave_length_mm", zl);
  S.params.num("floor_tilt_mm", t1);
  S.params.num("floor_saddle_mm", t2);
  std::vector<double> ba;
  for (const auto &b : bumps) ba.push_back(b.amp);
  S.params.raw("floor_bump_amp_mm", num_array(ba));
  S.params.num("floor_blend_mm", S.floor_blend_mm);
  return S;
}

Shape make_shape(Family f, Rng &rng) {
  switch (f) {
    case Family::Cylinder: return cylinder_like(rng, 105.0, 115.0, 280.0, 300.0, 720, 1.0);
    case Family::Protrusions: return protrusions(rng);
    case Family::Textured: return textured(rng);
    case Family::Tapered: return tapered(rng);
    case Family::Bowl: return bowl(rng);
    case Family::Necking: return necking(rng);
    case Family::Bulge: return bulge(rng);
    case Family::Elliptical: return elliptical(rng);
    case Family::HandDug: return hand_dug(rng);
    case Family::ShallowWide: return cylinder_like(rng, 195.0, 205.0, 98.0, 102.0, 1440, 0.5);
    case Family::DeepNarrow: return cylinder_like(rng, 72.0, 78.0, 390.0, 410.0, 720, 1.0);
    case Family::RoundedBowl: return rounded_bowl(rng);
    default: return cylinder_like(rng, 105.0, 115.0, 280.0, 300.0, 720, 1.0);
  }
}

const char *const kNames[] = {"cylinder", "protrusions", "textured",  "tapered",
                              "bowl",     "necking",     "bulge",     "elliptical",
                              "hand_dug", "shallow_wide", "deep_narrow", "rounded_bowl"};

std::string normalise(const std::string &s) {
  std::string o;
  for (char c : s)
    if (c != '_' && c != '-' && c != ' ')
      o += static_cast<char>((c >= 'A' && c <= 'Z') ? c - 'A' + 'a' : c);
  return o;
}

}  // namespace

const char *family_name(Family f) {
  const int i = static_cast<int>(f);
  if (i < 0 || i >= static_cast<int>(Family::kCount)) return "unknown";
  return kNames[i];
}

bool family_from_name(const std::string &name, Family *out) {
  const std::string n = normalise(name);
  for (int i = 0; i < static_cast<int>(Family::kCount); ++i)
    if (normalise(kNames[i]) == n) {
      if (out) *out = static_cast<Family>(i);
      return true;
    }
  return false;
}

Pit make_pit(Family f, bool ground, uint64_t seed, const PitOptions &opt) {
  if (static_cast<int>(f) < 0 || f >= Family::kCount) f = Family::Cylinder;
  Rng rng(mix_seed(seed, static_cast<uint64_t>(f) + 1));
  Shape S = make_shape(f, rng);
  if (opt.depth_mm > 0.0) {
    // Only where nothing else was drawn relative to the depth.
    if (f != Family::Cylinder && f != Family::ShallowWide && f != Family::DeepNarrow)
      throw std::invalid_argument("make_pit: a depth override needs a cylinder-like family");
    S.h = q(opt.depth_mm);
    S.t = build_levels(0.0, S.h, S.ring_step_mm, S.ring_step_mm, {});
  }
  if (opt.scale_xy != 1.0 || opt.scale_z != 1.0) {
    // Stretch the drawn shape: heights by sz, radii and floor positions by
    // sx, floor relief by sz.
    const double sx = opt.scale_xy, sz = opt.scale_z;
    if (!(sx > 0.0 && sz > 0.0)) throw std::invalid_argument("make_pit: scales must be positive");
    S.h = q(S.h * sz);
    for (double &t : S.t) t *= sz;
    S.t.back() = S.h;
    const auto r0 = S.radius;
    S.radius = [r0, sx, sz](double th, double t) { return sx * r0(th, t / sz); };
    if (S.floor) {
      const auto f0 = S.floor;
      S.floor = [f0, sx, sz](double x, double y, double s, double th) {
        return sz * f0(x / sx, y / sx, s, th);
      };
    }
    S.floor_blend_mm *= sz;
    S.ring_step_mm *= sz;
  }
  if (!opt.grooves.empty()) {
    const auto r0 = S.radius;
    const std::vector<PitOptions::Groove> gr = opt.grooves;
    S.radius = [r0, gr](double th, double t) {
      double r = r0(th, t);
      for (const auto &g : gr) {
        const double u = t - (g.z_mm + g.tilt_mm * std::sin(th - g.phase_rad));
        if (std::fabs(u) < 0.5 * g.width_mm)
          r += g.depth_mm * 0.5 * (1.0 + std::cos(kTwoPi * u / g.width_mm));
      }
      return r;
    };
    // Rings at most 0.5 mm (and a tenth of the groove) apart across each.
    std::vector<double> t = S.t;
    const double lo = S.t.front(), hi = S.t.back();
    for (const auto &g : gr) {
      const double a = std::max(lo, g.z_mm - 0.5 * g.width_mm - std::fabs(g.tilt_mm));
      const double b = std::min(hi, g.z_mm + 0.5 * g.width_mm + std::fabs(g.tilt_mm));
      if (b <= a) continue;
      const double step = std::min(0.5, 0.1 * g.width_mm);
      const int n = static_cast<int>(std::ceil((b - a) / step));
      for (int i = 0; i <= n; ++i) t.push_back(a + (b - a) * i / n);
    }
    std::sort(t.begin(), t.end());
    S.t.clear();
    for (double z : t)
      if (S.t.empty() || z - S.t.back() > 1e-3) S.t.push_back(z);
    S.t.back() = hi;
  }
  // The stone and the lumps, summed onto the floor (one stone: as before).
  std::vector<PitOptions::Bump> bumps;
  if (opt.stone_height_mm != 0.0)
    bumps.push_back({opt.stone_height_mm, opt.stone_radius_mm, opt.stone_x_mm, opt.stone_y_mm});
  bumps.insert(bumps.end(), opt.lumps.begin(), opt.lumps.end());
  if (!bumps.empty()) {
    auto base = S.floor;
    S.floor = [base, bumps](double x, double y, double s, double th) {
      double acc = base ? base(x, y, s, th) : 0.0;
      for (const auto &b : bumps) {
        const double d = std::hypot(x - b.x_mm, y - b.y_mm);
        acc += d < b.radius_mm ? 0.5 * b.height_mm * (1.0 + std::cos(kPi * d / b.radius_mm)) : 0.0;
      }
      return acc;
    };
  }
  return build(S, f, ground, seed, opt, bumps);
}

double stone_volume_mm3(double height_mm, double radius_mm) {
  // 2 pi int_0^a r H (1 + cos(pi r / a)) / 2 dr = pi H a^2 (1/2 - 2 / pi^2).
  return kPi * height_mm * radius_mm * radius_mm * (0.5 - 2.0 / (kPi * kPi));
}

double signed_volume_mm3(const Mesh &m) {
  const size_t nv = m.vertices();
  if (nv == 0 || m.tri.empty()) return 0.0;
  // Evaluate about the vertex centroid: the sum is origin-independent for a
  // closed mesh, and small lever arms keep the terms well conditioned.
  double c[3] = {0.0, 0.0, 0.0};
  for (size_t i = 0; i < nv; ++i)
    for (int k = 0; k < 3; ++k) c[k] += static_cast<double>(m.xyz[3 * i + k]);
  for (double &ck : c) ck /= static_cast<double>(nv);
  double sum = 0.0, comp = 0.0;  // Neumaier
  const size_t nt = m.triangles();
  for (size_t t = 0; t < nt; ++t) {
    double p[3][3];
    for (int a = 0; a < 3; ++a) {
      const size_t vi = m.tri[3 * t + a];
      for (int k = 0; k < 3; ++k) p[a][k] = static_cast<double>(m.xyz[3 * vi + k]) - c[k];
    }
    const double cx = p[1][1] * p[2][2] - p[1][2] * p[2][1];
    const double cy = p[1][2] * p[2][0] - p[1][0] * p[2][2];
    const double cz = p[1][0] * p[2][1] - p[1][1] * p[2][0];
    const double term = p[0][0] * cx + p[0][1] * cy + p[0][2] * cz;
    const double s = sum + term;
    if (std::fabs(sum) >= std::fabs(term))
      comp += (sum - s) + term;
    else
      comp += (term - s) + sum;
    sum = s;
  }
  return (sum + comp) / 6.0;
}

// Divergence theorem with F = (0, 0, z - h) over {inside, z < h}: div F = 1,
// and F vanishes on the cut plane, so the volume is the sum over the mesh
// below h (triangles clipped at the plane) of the integral of (z - h) n_z,
// exact for a linear integrand: (centroid z - h) times the z-component of
// the triangle's area vector (normals outward: counter-clockwise seen from
// outside the void, as Mesh documents).
double volume_below_mm3(const Mesh &m, double h_mm) {
  auto term = [h_mm](const double *a, const double *b, const double *c) {
    const double nz = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    return ((a[2] + b[2] + c[2]) / 3.0 - h_mm) * nz;
  };
  double below_sum = 0.0;
  const size_t nt = m.triangles();
  for (size_t t = 0; t < nt; ++t) {
    double p[3][3];
    int below = 0;
    for (int a = 0; a < 3; ++a) {
      const size_t vi = m.tri[3 * t + a];
      for (int k = 0; k < 3; ++k) p[a][k] = static_cast<double>(m.xyz[3 * vi + k]);
      below += p[a][2] < h_mm;
    }
    if (below == 0) continue;
    // The part below the plane: the triangle, or a clipped triangle or
    // quadrilateral, vertices in order.
    double poly[4][3];
    int n = 0;
    for (int a = 0; a < 3; ++a) {
      const double *u = p[a], *v = p[(a + 1) % 3];
      if (u[2] < h_mm) {
        for (int k = 0; k < 3; ++k) poly[n][k] = u[k];
        ++n;
      }
      if ((u[2] < h_mm) != (v[2] < h_mm)) {
        const double s = (h_mm - u[2]) / (v[2] - u[2]);
        for (int k = 0; k < 3; ++k) poly[n][k] = u[k] + s * (v[k] - u[k]);
        ++n;
      }
    }
    for (int k = 1; k + 1 < n; ++k) below_sum += term(poly[0], poly[k], poly[k + 1]);
  }
  return below_sum;
}

}  // namespace pv::sim
