// Procedural pits: the mesh volumes against independent closed forms, mesh
// topology (watertight, consistently oriented), determinism, what the
// scanned mesh contains, and the origin-independence of the signed volume.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <utility>
#include <string>
#include <vector>

#include "sim/pit_geometry.h"

#include "pv_cmocka.h"

using pv::sim::Family;
using pv::sim::Mesh;
using pv::sim::Pit;
using pv::sim::PitOptions;

namespace {

constexpr double kPi = 3.14159265358979323846;

double jnum(const std::string &js, const char *key) {
  const std::string k = std::string("\"") + key + "\":";
  const size_t p = js.find(k);
  if (p == std::string::npos) {
    print_error("params_json lacks %s: %s\n", key, js.c_str());
    fail();
  }
  return std::strtod(js.c_str() + p + k.size(), nullptr);
}

std::vector<double> jarray(const std::string &js, const char *key) {
  const std::string k = std::string("\"") + key + "\":[";
  const size_t p = js.find(k);
  assert_true(p != std::string::npos);
  std::vector<double> v;
  const char *c = js.c_str() + p + k.size();
  while (*c != ']') {
    char *end = nullptr;
    v.push_back(std::strtod(c, &end));
    c = end;
    if (*c == ',') ++c;
  }
  return v;
}

double rel(double a, double b) { return std::fabs(a - b) / std::fabs(b); }

void vtx(const Mesh &m, size_t i, double p[3]) {
  for (int k = 0; k < 3; ++k) p[k] = static_cast<double>(m.xyz[3 * i + k]);
}

uint64_t key(uint32_t a, uint32_t b) { return (static_cast<uint64_t>(a) << 32) | b; }

// Directed edges sorted; returns false on a duplicate directed edge.
bool directed_edges(const Mesh &m, std::vector<uint64_t> *out) {
  out->clear();
  out->reserve(m.tri.size());
  for (size_t t = 0; t < m.triangles(); ++t)
    for (int e = 0; e < 3; ++e) out->push_back(key(m.tri[3 * t + e], m.tri[3 * t + (e + 1) % 3]));
  std::sort(out->begin(), out->end());
  return std::adjacent_find(out->begin(), out->end()) == out->end();
}

bool has(const std::vector<uint64_t> &sorted, uint64_t k) {
  return std::binary_search(sorted.begin(), sorted.end(), k);
}

void check_watertight(const Mesh &m) {
  for (size_t t = 0; t < m.triangles(); ++t) {
    const uint32_t a = m.tri[3 * t], b = m.tri[3 * t + 1], c = m.tri[3 * t + 2];
    assert_true(a != b && b != c && a != c);
    assert_true(a < m.vertices() && b < m.vertices() && c < m.vertices());
  }
  std::vector<uint64_t> e;
  assert_true(directed_edges(m, &e));  // each directed edge at most once
  for (uint64_t k : e) {               // ... and its reverse exactly once
    const uint32_t a = static_cast<uint32_t>(k >> 32), b = static_cast<uint32_t>(k);
    if (!has(e, key(b, a))) {
      print_error("open edge %u-%u\n", a, b);
      fail();
    }
  }
}

// The lid (void_closed triangles in the rim plane): a fan; returns the rim
// polygon in angular order.
struct Rim {
  std::vector<double> ang, x, y;
  // Inside the rim polygon (a star-shaped fan about the origin)?
  bool inside(double px, double py) const {
    const double a = std::atan2(py, px);
    size_t i = std::upper_bound(ang.begin(), ang.end(), a) - ang.begin();
    const size_t n = ang.size();
    const size_t i1 = (i + n - 1) % n, i2 = i % n;
    // Same side of edge i1->i2 as the origin?
    const double cr = (x[i2] - x[i1]) * (py - y[i1]) - (y[i2] - y[i1]) * (px - x[i1]);
    return cr > 0.0;
  }
  double max_r() const {
    double m = 0;
    for (size_t i = 0; i < x.size(); ++i) m = std::max(m, std::hypot(x[i], y[i]));
    return m;
  }
  double area() const {
    double a = 0;
    for (size_t i = 0; i < x.size(); ++i) {
      const size_t j = (i + 1) % x.size();
      a += x[i] * y[j] - x[j] * y[i];
    }
    return 0.5 * a;
  }
};

Rim rim_of(const Pit &p) {
  const Mesh &v = p.void_closed;
  const float rz = static_cast<float>(p.rim_z_mm);
  std::vector<std::pair<double, size_t>> pts;
  for (size_t t = 0; t < v.triangles(); ++t) {
    bool plane = true;
    for (int e = 0; e < 3; ++e) plane = plane && v.xyz[3 * v.tri[3 * t + e] + 2] == rz;
    if (!plane) continue;
    for (int e = 0; e < 3; ++e) {
      double q[3];
      vtx(v, v.tri[3 * t + e], q);
      if (q[0] != 0.0 || q[1] != 0.0) pts.push_back({std::atan2(q[1], q[0]), v.tri[3 * t + e]});
    }
  }
  std::sort(pts.begin(), pts.end());
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  Rim r;
  for (const auto &pt : pts) {
    double q[3];
    vtx(v, pt.second, q);
    r.ang.push_back(pt.first);
    r.x.push_back(q[0]);
    r.y.push_back(q[1]);
  }
  return r;
}

void check_scanned(const Pit &p) {
  const Mesh &s = p.scanned, &v = p.void_closed;
  // Shares the wall and floor vertices with void_closed (all but the lid centre).
  assert_true(s.vertices() >= v.vertices() - 1);
  assert_memory_equal(s.xyz.data(), v.xyz.data(), (v.xyz.size() - 3) * sizeof(float));
  const Rim rim = rim_of(p);
  assert_true(rim.x.size() >= 360);
  const float rz = static_cast<float>(p.rim_z_mm);
  double plane_area = 0.0, outside_area = 0.0;
  for (size_t t = 0; t < s.triangles(); ++t) {
    double q[3][3];
    bool plane = true;
    for (int e = 0; e < 3; ++e) {
      vtx(s, s.tri[3 * t + e], q[e]);
      plane = plane && s.xyz[3 * s.tri[3 * t + e] + 2] == rz;
    }
    if (!plane) continue;
    const double cx = (q[0][0] + q[1][0] + q[2][0]) / 3, cy = (q[0][1] + q[1][1] + q[2][1]) / 3;
    if (rim.inside(cx, cy)) {
      print_error("%s: lid triangle in the scanned mesh at (%g, %g)\n", p.params_json.c_str(),
                  cx, cy);
      fail();
    }
    // Facing down (into the soil), like the wall next to it.
    const double a = 0.5 * ((q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) -
                            (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]));
    assert_true(a < 0.0);
    plane_area -= a;
    if (std::hypot(cx, cy) > rim.max_r()) outside_area -= a;
  }
  // Open edges: only the rim (no ground) or the outer ground circle.
  std::vector<uint64_t> e;
  assert_true(directed_edges(s, &e));
  size_t open = 0;
  for (uint64_t k : e) {
    const uint32_t a = static_cast<uint32_t>(k >> 32), b = static_cast<uint32_t>(k);
    if (has(e, key(b, a))) continue;
    ++open;
    for (uint32_t i : {a, b}) {
      double q[3];
      vtx(s, i, q);
      assert_true(q[2] == p.rim_z_mm);
      if (p.ground) assert_true(std::fabs(std::hypot(q[0], q[1]) - p.ground_outer_radius_mm) < 1e-3);
    }
  }
  assert_int_equal(open, rim.x.size());
  if (p.ground) {
    const double rg = p.ground_outer_radius_mm;
    double outer = 0.0;  // polygon on the circle, at the rim's angles
    for (size_t i = 0; i < rim.ang.size(); ++i) {
      const double d = (i + 1 < rim.ang.size() ? rim.ang[i + 1] : rim.ang[0] + 2 * kPi) - rim.ang[i];
      outer += 0.5 * rg * rg * std::sin(d);
    }
    if (rel(plane_area, outer - rim.area()) > 1e-6) {
      print_error("ground area %.6f expected %.6f (outer %.6f rim %.6f)\n", plane_area,
                  outer - rim.area(), outer, rim.area());
      fail();
    }
    assert_true(outside_area > 0.5 * (kPi * rg * rg - kPi * rim.max_r() * rim.max_r()));
    assert_true(rg >= rim.max_r() + 40.0 - 1e-3 && rg <= rim.max_r() + 80.0 + 1e-3);
  } else {
    assert_true(plane_area == 0.0);
    assert_true(p.ground_outer_radius_mm == 0.0);
  }
}

// Independent nominal volume of the intended (continuous) shape.
double nominal_volume(const Pit &p, double *tol) {
  const std::string &js = p.params_json;
  const double h = p.rim_z_mm;
  switch (p.family) {
    case Family::Cylinder:
    case Family::ShallowWide:
    case Family::DeepNarrow: {
      const double R = jnum(js, "radius_mm");
      *tol = 2e-5;  // inscribed polygon, 720 or 1440 angles
      return kPi * R * R * h;
    }
    case Family::Protrusions: {
      // Each block: int int (R^2 - (R - d B)^2) / 2 dtheta dz, B = smooth boxes
      // (smoothstep edges of width tw): int B = width, int B^2 = width - 0.2571 tw.
      const double R = jnum(js, "radius_mm"), tw = jnum(js, "side_transition_mm");
      const double s2 = 1.0 - 2.0 * (9.0 / 5.0 - 2.0 + 4.0 / 7.0);
      double v = kPi * R * R * h;
      size_t n = 0;
      for (size_t at = js.find("{\"theta_rad\""); at != std::string::npos;
           at = js.find("{\"theta_rad\"", at + 1), ++n) {
        const std::string b = js.substr(at, js.find('}', at) - at + 1);
        const double arc = jnum(b, "arc_mm"), ht = jnum(b, "height_mm"), d = jnum(b, "protrusion_mm");
        v -= R * d * (arc / R) * ht - 0.5 * d * d * ((arc - s2 * tw) / R) * (ht - s2 * tw);
      }
      assert_true(n >= 4 && n <= 8);
      *tol = 1e-4;
      return v;
    }
    case Family::Textured: {
      // Lining cylinder plus the grooves (raised cosines: cross-section d w / 2
      // each, swept around the wall); the roughness averages out.
      const double R = jnum(js, "radius_mm") - jnum(js, "lining_mm");
      const auto w = jarray(js, "groove_width_mm"), d = jarray(js, "groove_depth_mm");
      double v = kPi * R * R * h;
      for (size_t i = 0; i < w.size(); ++i) v += 2 * kPi * R * 0.5 * d[i] * w[i];
      *tol = 2e-3;
      return v;
    }
    case Family::Tapered: {
      const double a = jnum(js, "r_bottom_mm"), b = jnum(js, "r_top_mm");
      *tol = 2e-5;
      return kPi * h / 3 * (a * a + b * b + a * b);
    }
    case Family::Bowl: {
      const double R = jnum(js, "radius_mm"), c = jnum(js, "cap_height_mm");
      *tol = 5e-5;
      return kPi * R * R * (h - c) + 2.0 / 3.0 * kPi * R * R * c;
    }
    case Family::Necking: {
      // Simpson on pi r(z)^2 of the analytic profile.
      const double R = jnum(js, "radius_mm"), a = jnum(js, "neck_amp_mm"),
                   zc = jnum(js, "neck_z_mm"), w = jnum(js, "neck_width_mm");
      const int n = 20000;
      double s = 0;
      for (int i = 0; i <= n; ++i) {
        const double z = h * i / n, u = (z - zc) / w, r = R - a * std::exp(-u * u);
        s += (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2)) * kPi * r * r;
      }
      *tol = 5e-5;
      return s * h / n / 3;
    }
    case Family::Bulge: {
      const double R = jnum(js, "radius_mm"), b = jnum(js, "bulge_amp_mm");
      const double hu = 0.5 * jnum(js, "bulge_width_mm"), hz = 0.5 * jnum(js, "bulge_height_mm");
      *tol = 5e-5;
      // int int ((R + b B)^2 - R^2) / 2 dtheta dz, B = raised cosines in arc and z.
      return kPi * R * R * h + b * hu * hz + 0.28125 * b * b * hu * hz / R;
    }
    case Family::Elliptical: {
      const double a = jnum(js, "a_mm"), b = jnum(js, "b_mm");
      *tol = 5e-4;
      return kPi * a * b * h;
    }
    case Family::HandDug: {
      const double R = jnum(js, "radius_mm");
      *tol = 0.02;  // harmonics of a few % and a floor of a few mm
      return kPi * R * R * h;
    }
    case Family::RoundedBowl: {
      // The half-ellipsoid under its wall; the cap's rings are about 1 mm
      // of arc apart (an inscribed polyline: slightly less).
      const double R = jnum(js, "radius_mm"), c = jnum(js, "cap_height_mm");
      *tol = 1e-4;
      return kPi * R * R * (h - c) + 2.0 / 3.0 * kPi * R * R * c;
    }
    default: *tol = 0; return 0;
  }
}

void test_cylinder_exact_polygon(void **) {
  for (uint64_t seed : {1ull, 2ull, 99ull}) {
    const Pit p = make_pit(Family::Cylinder, false, seed);
    const double R = jnum(p.params_json, "radius_mm"), h = jnum(p.params_json, "depth_mm");
    const double N = jnum(p.params_json, "angles");
    assert_true(N == 720);
    assert_true(R >= 105 && R <= 115 && h >= 280 && h <= 300);
    assert_true(h == p.rim_z_mm);
    const double exact = 0.5 * N * R * R * std::sin(2 * kPi / N) * h;
    print_message("cylinder seed %llu: R %.4f h %.4f V %.6f exact polygon %.6f rel %.2e pi r^2 h rel %.2e\n",
                  static_cast<unsigned long long>(seed), R, h, p.volume_mm3, exact,
                  rel(p.volume_mm3, exact), rel(p.volume_mm3, kPi * R * R * h));
    assert_true(rel(p.volume_mm3, exact) < 1e-9);
    assert_true(p.volume_mm3 < kPi * R * R * h);
    assert_true(rel(p.volume_mm3, kPi * R * R * h) < 1.4e-5);
    assert_true(std::fabs(p.max_radius_mm - R) < 1e-4);
  }
}

void test_tapered_frustum(void **) {
  for (uint64_t seed : {3ull, 4ull, 5ull}) {
    const Pit p = make_pit(Family::Tapered, false, seed);
    const double a = jnum(p.params_json, "r_bottom_mm"), b = jnum(p.params_json, "r_top_mm");
    const double h = p.rim_z_mm, N = jnum(p.params_json, "angles");
    assert_true(a >= 80 && a <= 100 && b >= 120 && b <= 140);
    const double k = 0.5 * N * std::sin(2 * kPi / N);
    const double A1 = k * a * a, A2 = k * b * b;
    const double exact = h / 3 * (A1 + A2 + std::sqrt(A1 * A2));
    print_message("tapered seed %llu: V %.6f frustum %.6f rel %.2e\n",
                  static_cast<unsigned long long>(seed), p.volume_mm3, exact,
                  rel(p.volume_mm3, exact));
    assert_true(rel(p.volume_mm3, exact) < 1e-9);
  }
}

// The volume below a plane: the frustum of a tapered pit cut at height z
// (polygon sections grow quadratically), zero under the floor, the whole
// volume above the rim.
void test_volume_below(void **) {
  const Pit p = make_pit(Family::Tapered, false, 3);
  const double a = jnum(p.params_json, "r_bottom_mm"), b = jnum(p.params_json, "r_top_mm");
  const double h = p.rim_z_mm, N = jnum(p.params_json, "angles");
  const double k = 0.5 * N * std::sin(2 * kPi / N);
  for (double z : {1.0, 37.5, 100.25, 0.5 * h, h - 2.0}) {
    const double r = a + (b - a) * z / h;
    const double A1 = k * a * a, A2 = k * r * r;
    const double exact = z / 3 * (A1 + A2 + std::sqrt(A1 * A2));
    const double v = pv::sim::volume_below_mm3(p.void_closed, z);
    print_message("tapered below %.2f: %.6f frustum %.6f rel %.2e\n", z, v, exact, rel(v, exact));
    assert_true(rel(v, exact) < 1e-8);
  }
  assert_true(std::fabs(pv::sim::volume_below_mm3(p.void_closed, -1.0)) < 1e-9);
  assert_true(rel(pv::sim::volume_below_mm3(p.void_closed, h + 1.0), p.volume_mm3) < 1e-12);
}

void test_elliptical(void **) {
  for (uint64_t seed : {6ull, 7ull, 8ull}) {
    const Pit p = make_pit(Family::Elliptical, false, seed);
    const double a = jnum(p.params_json, "a_mm"), b = jnum(p.params_json, "b_mm");
    const double h = p.rim_z_mm, N = jnum(p.params_json, "angles");
    assert_true(a >= 120 && a <= 140 && b >= 80 && b <= 100);
    const double V = kPi * a * b * h;
    // Inscribed polygon: each chord cuts off at most kappa_max L^3 / 12,
    // kappa_max = a / b^2, L <= a dtheta (a / b), perimeter <= 2 pi a.
    const double L = a * (2 * kPi / N) * (a / b);
    const double bound = 1.01 * (a / (b * b)) / 12 * L * L * 2 * kPi * a * h;
    print_message("elliptical seed %llu: a %.3f b %.3f V %.3f pi a b h %.3f deficit %.3e (bound %.3e)\n",
                  static_cast<unsigned long long>(seed), a, b, p.volume_mm3, V,
                  (V - p.volume_mm3) / V, bound / V);
    assert_true(p.volume_mm3 < V);
    assert_true(V - p.volume_mm3 < bound);
    assert_true(std::fabs(p.max_radius_mm - a) < 0.01);
  }
}

void test_all_families(void **) {
  for (int fi = 0; fi < static_cast<int>(Family::kCount); ++fi) {
    const Family f = static_cast<Family>(fi);
    pv::sim::Family back;
    assert_true(pv::sim::family_from_name(pv::sim::family_name(f), &back));
    assert_true(back == f);
    const Pit p0 = make_pit(f, false, 7);
    const Pit p1 = make_pit(f, true, 7);
    for (const Pit *p : {&p0, &p1}) {
      check_watertight(p->void_closed);
      check_scanned(*p);
      assert_true(p->volume_mm3 > 0);
      assert_true(p->volume_mm3 == pv::sim::signed_volume_mm3(p->void_closed));
      assert_true(p->void_closed.triangles() < 1500000);
      assert_true(p->params_json.front() == '{' && p->params_json.back() == '}');
      // No vertex above the rim plane; max_radius covers the wall.
      double zmax = -1e9, rmax = 0;
      for (size_t i = 0; i < p->void_closed.vertices(); ++i) {
        double q[3];
        vtx(p->void_closed, i, q);
        zmax = std::max(zmax, q[2]);
        rmax = std::max(rmax, std::hypot(q[0], q[1]));
      }
      assert_true(zmax == p->rim_z_mm);
      assert_true(std::fabs(rmax - p->max_radius_mm) < 1e-9);
    }
    // The ground ring changes only the scanned mesh.
    assert_true(p0.void_closed.xyz == p1.void_closed.xyz);
    assert_true(p0.void_closed.tri == p1.void_closed.tri);
    assert_true(p0.volume_mm3 == p1.volume_mm3);
    assert_true(p1.ground_outer_radius_mm > p1.max_radius_mm);
    double tol = 0;
    const double nom = nominal_volume(p0, &tol);
    print_message("%-12s tris void %7zu scanned %7zu (+ground %7zu) V %.1f mm3 (%.4f L) "
                  "nominal %.1f rel %+.2e  max_r %.2f depth %.2f\n",
                  pv::sim::family_name(f), p0.void_closed.triangles(), p0.scanned.triangles(),
                  p1.scanned.triangles(), p0.volume_mm3, p0.volume_mm3 * 1e-6, nom,
                  (p0.volume_mm3 - nom) / nom, p0.max_radius_mm, p0.rim_z_mm);
    if (rel(p0.volume_mm3, nom) > tol) {
      print_error("%s: volume %.3f vs nominal %.3f (tol %g)\n", p0.params_json.c_str(),
                  p0.volume_mm3, nom, tol);
      fail();
    }
  }
}

void test_family_ranges(void **) {
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    {
      const Pit p = make_pit(Family::Protrusions, false, seed);
      const std::string &js = p.params_json;
      size_t n = 0;
      for (size_t at = js.find("\"arc_mm\""); at != std::string::npos;
           at = js.find("\"arc_mm\"", at + 1)) {
        ++n;
        const double arc = std::strtod(js.c_str() + at + 9, nullptr);
        assert_true(arc >= 20 && arc <= 60);
      }
      assert_true(n >= 4 && n <= 8);
    }
    {
      const Pit p = make_pit(Family::Textured, false, seed);
      const auto z = jarray(p.params_json, "groove_z_mm");
      const auto w = jarray(p.params_json, "groove_width_mm");
      const auto d = jarray(p.params_json, "groove_depth_mm");
      assert_true(z.size() >= 8);
      for (size_t i = 0; i < z.size(); ++i) {
        assert_true(w[i] >= 3 && w[i] <= 6 && d[i] >= 2 && d[i] <= 4);
        if (i) assert_true(z[i] - z[i - 1] >= 15 && z[i] - z[i - 1] <= 30);
      }
    }
    {
      const Pit p = make_pit(Family::ShallowWide, false, seed);
      const double R = jnum(p.params_json, "radius_mm");
      assert_true(R >= 195 && R <= 205 && p.rim_z_mm >= 98 && p.rim_z_mm <= 102);
      const Pit d = make_pit(Family::DeepNarrow, false, seed);
      const double r = jnum(d.params_json, "radius_mm");
      assert_true(r >= 72 && r <= 78 && d.rim_z_mm >= 390 && d.rim_z_mm <= 410);
    }
    {
      const Pit p = make_pit(Family::Necking, false, seed);
      const double a = jnum(p.params_json, "neck_amp_mm");
      assert_true(a >= 15 && a <= 30);
      const Pit b = make_pit(Family::Bulge, false, seed);
      const double amp = jnum(b.params_json, "bulge_amp_mm");
      assert_true(amp >= 15 && amp <= 30);
      assert_true(std::fabs(b.max_radius_mm - jnum(b.params_json, "radius_mm") - amp) < 0.5);
    }
  }
}

void test_deterministic(void **) {
  for (int fi = 0; fi < static_cast<int>(Family::kCount); ++fi) {
    const Family f = static_cast<Family>(fi);
    const Pit a = make_pit(f, true, 12345), b = make_pit(f, true, 12345),
              c = make_pit(f, true, 12346);
    assert_true(a.scanned.xyz.size() == b.scanned.xyz.size());
    assert_memory_equal(a.scanned.xyz.data(), b.scanned.xyz.data(),
                        a.scanned.xyz.size() * sizeof(float));
    assert_true(a.scanned.tri == b.scanned.tri);
    assert_true(a.void_closed.xyz == b.void_closed.xyz && a.void_closed.tri == b.void_closed.tri);
    assert_string_equal(a.params_json.c_str(), b.params_json.c_str());
    assert_memory_equal(&a.volume_mm3, &b.volume_mm3, sizeof(double));
    assert_true(a.void_closed.xyz != c.void_closed.xyz);
    assert_true(a.volume_mm3 != c.volume_mm3);
    assert_true(a.params_json != c.params_json);
  }
}

// Translations and quarter turns about Z that are exact in float: snap the
// mesh to a 1/1024 mm grid first (then +-4096 mm offsets stay exact).
void test_volume_origin_independent(void **) {
  for (Family f : {Family::Cylinder, Family::HandDug, Family::Elliptical, Family::Protrusions}) {
    const Pit p = make_pit(f, false, 21);
    Mesh m = p.void_closed;
    for (float &x : m.xyz) x = std::round(x * 1024.0f) / 1024.0f;
    const double v0 = pv::sim::signed_volume_mm3(m);
    assert_true(rel(v0, p.volume_mm3) < 1e-5);
    const double offs[][3] = {{4096.25, -2048.5, 1000.125}, {-3000.0, 3500.75, -4000.5},
                              {0.015625, 0.0, 0.0}};
    for (int turn = 0; turn < 4; ++turn)
      for (const auto &o : offs) {
        Mesh t = m;
        for (size_t i = 0; i < t.vertices(); ++i) {
          float x = t.xyz[3 * i], y = t.xyz[3 * i + 1];
          for (int r = 0; r < turn; ++r) {
            const float nx = -y;
            y = x;
            x = nx;
          }
          t.xyz[3 * i] = x + static_cast<float>(o[0]);
          t.xyz[3 * i + 1] = y + static_cast<float>(o[1]);
          t.xyz[3 * i + 2] += static_cast<float>(o[2]);
          // Exact: still on the 1/1024 grid.
          assert_true(static_cast<double>(t.xyz[3 * i]) ==
                      static_cast<double>(x) + o[0]);
        }
        const double v = pv::sim::signed_volume_mm3(t);
        assert_true(rel(v, v0) < 1e-12);
      }
    // Reversed orientation flips the sign.
    Mesh r = m;
    for (size_t t = 0; t < r.triangles(); ++t) std::swap(r.tri[3 * t + 1], r.tri[3 * t + 2]);
    assert_true(rel(-pv::sim::signed_volume_mm3(r), v0) < 1e-14);
    // An arbitrary rotation re-rounds every vertex to float: the volume moves
    // only by that rounding (~1e-10), far below any accuracy of interest.
    Mesh a = p.void_closed;
    const double th = 0.7371, cs = std::cos(th), sn = std::sin(th);
    for (size_t i = 0; i < a.vertices(); ++i) {
      const double x = a.xyz[3 * i], y = a.xyz[3 * i + 1];
      a.xyz[3 * i] = static_cast<float>(cs * x - sn * y + 250.0);
      a.xyz[3 * i + 1] = static_cast<float>(sn * x + cs * y - 125.0);
    }
    assert_true(rel(pv::sim::signed_volume_mm3(a), p.volume_mm3) < 1e-8);
  }
}

// ---------------------------------------------------------------------------
// Stress options (PitOptions).

// The default options change nothing: the standard corpus's pits are the
// pits they were (build() paths: plain floor, floor function with the wall
// blend, closing vertex, 1440 angles; test_corpus_sets pins hashes too).
void test_default_options_identical(void **) {
  for (Family f : {Family::Cylinder, Family::HandDug, Family::Bowl, Family::ShallowWide}) {
    const Pit a = make_pit(f, true, 2), b = make_pit(f, true, 2, PitOptions());
    assert_true(a.scanned.xyz == b.scanned.xyz && a.scanned.tri == b.scanned.tri);
    assert_true(a.void_closed.xyz == b.void_closed.xyz);
    assert_memory_equal(&a.volume_mm3, &b.volume_mm3, sizeof(double));
    assert_string_equal(a.params_json.c_str(), b.params_json.c_str());
  }
  // The ground ring is the tail of the scanned triangles.
  const Pit g = make_pit(Family::HandDug, true, 2), n = make_pit(Family::HandDug, false, 2);
  assert_int_equal(g.ground_triangles, g.scanned.triangles() - n.scanned.triangles());
  assert_int_equal(n.ground_triangles, 0);
}

// Raised-cosine stone: V = 2 pi int_0^a r H (1 + cos(pi r / a)) / 2 dr, here
// by composite Simpson (independent of the closed form in the library).
double stone_simpson(double H, double a) {
  const int n = 2000;
  double s = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double r = a * i / n;
    const double f = 2 * kPi * r * 0.5 * H * (1 + std::cos(kPi * r / a));
    s += f * (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2));
  }
  return s * (a / n) / 3;
}

void test_stone(void **) {
  PitOptions o;
  o.stone_height_mm = 40.0;
  o.stone_radius_mm = 35.0;
  o.stone_x_mm = 35.0;
  o.stone_y_mm = -20.0;
  const double exact = stone_simpson(40.0, 35.0);
  assert_true(rel(pv::sim::stone_volume_mm3(40.0, 35.0), exact) < 1e-12);
  for (const auto &fs : {std::make_pair(Family::Cylinder, 1ull), std::make_pair(Family::HandDug, 7ull)}) {
      const Family f = fs.first;
      const uint64_t seed = fs.second;
      const Pit p0 = make_pit(f, true, seed), p = make_pit(f, true, seed, o);
      check_watertight(p.void_closed);
      check_scanned(p);
      // The wall is untouched; the void loses the stone.
      const size_t wall = 3 * static_cast<size_t>(jnum(p.params_json, "angles") *
                                                  jnum(p.params_json, "rings"));
      assert_memory_equal(p.void_closed.xyz.data(), p0.void_closed.xyz.data(),
                          wall * sizeof(float));
      const double lost = p0.volume_mm3 - p.volume_mm3;
      print_message("stone on %s seed %llu: void %.1f -> %.1f mm3, lost %.3f mm3, "
                    "stone %.3f mm3 (rel %+.2e)\n", pv::sim::family_name(f),
                    static_cast<unsigned long long>(seed), p0.volume_mm3, p.volume_mm3, lost,
                    exact, (lost - exact) / exact);
      assert_true(rel(lost, exact) < 1e-4);  // the 2 mm floor grid samples the bump
      assert_true(rel(jnum(p.params_json, "stone_volume_mm3"), exact) < 1e-12);
      // Its top: within a grid cell of (35, -20), 40 mm above the floor there.
      if (f == Family::Cylinder) {
        double top = -1, tx = 0, ty = 0;
        for (size_t i = wall / 3; i + 1 < p.void_closed.vertices(); ++i) {
          double q[3];
          vtx(p.void_closed, i, q);
          if (q[2] > top) {
            top = q[2];
            tx = q[0];
            ty = q[1];
          }
        }
        assert_true(top > 39.5 && top <= 40.0 + 1e-4);
        assert_true(std::hypot(tx - 35.0, ty + 20.0) < 2.0);
      }
    }
  // Where it cannot be: a bowl (no floor grid), against the wall.
  bool threw = false;
  try {
    make_pit(Family::Bowl, false, 1, o);
  } catch (const std::invalid_argument &) {
    threw = true;
  }
  assert_true(threw);
  PitOptions wall = o;
  wall.stone_x_mm = 80.0;
  threw = false;
  try {
    make_pit(Family::Cylinder, false, 1, wall);
  } catch (const std::invalid_argument &) {
    threw = true;
  }
  assert_true(threw);
}

// The tilted ground: the lid is the ground plane itself, the ground ring lies
// on it, the wall is sheared onto it; cross-sections centred on the axis
// keep their volume (the plane's linear term integrates to zero over them).
void test_tilted_ground(void **) {
  PitOptions o;
  o.ground_tilt_deg = 4.0;
  o.ground_tilt_azimuth_rad = 1.0;
  const double gx = std::tan(4.0 * kPi / 180) * std::cos(1.0);
  const double gy = std::tan(4.0 * kPi / 180) * std::sin(1.0);
  for (const auto &fs : {std::make_pair(Family::Cylinder, 1ull), std::make_pair(Family::Tapered, 3ull),
                         std::make_pair(Family::Elliptical, 1ull)}) {
      const Family f = fs.first;
      const uint64_t seed = fs.second;
      const Pit p0 = make_pit(f, true, seed), p = make_pit(f, true, seed, o);
      check_watertight(p.void_closed);
      const double h = p.rim_z_mm;
      assert_true(h == p0.rim_z_mm);
      // Analytic volume of the untilted pit (polygon prism / frustum / ellipse).
      const double N = jnum(p.params_json, "angles"), k = 0.5 * N * std::sin(2 * kPi / N);
      double exact = 0, tol = 1e-8;
      if (f == Family::Cylinder) {
        const double R = jnum(p.params_json, "radius_mm");
        exact = k * R * R * h;
      } else if (f == Family::Tapered) {
        const double a = k * std::pow(jnum(p.params_json, "r_bottom_mm"), 2);
        const double b = k * std::pow(jnum(p.params_json, "r_top_mm"), 2);
        exact = h / 3 * (a + b + std::sqrt(a * b));
      } else {
        exact = p0.volume_mm3;  // itself checked against pi a b h above
      }
      print_message("tilted %s seed %llu: V %.3f untilted %.3f analytic %.3f rel %+.2e\n",
                    pv::sim::family_name(f), static_cast<unsigned long long>(seed), p.volume_mm3,
                    p0.volume_mm3, exact, (p.volume_mm3 - exact) / exact);
      assert_true(rel(p.volume_mm3, exact) < tol);
      assert_true(jnum(p.params_json, "ground_tilt_deg") == 4.0);
      // The lid (the last `angles` triangles) is the plane through the rim
      // height on the axis.
      const Mesh &v = p.void_closed;
      const size_t lid0 = v.triangles() - static_cast<size_t>(N);
      double worst = 0, zlo = 1e9, zhi = -1e9;
      for (size_t t = lid0; t < v.triangles(); ++t)
        for (int e = 0; e < 3; ++e) {
          double q[3];
          vtx(v, v.tri[3 * t + e], q);
          worst = std::max(worst, std::fabs(q[2] - (h + gx * q[0] + gy * q[1])));
          zlo = std::min(zlo, q[2]);
          zhi = std::max(zhi, q[2]);
        }
      // And nothing of the void above it.
      for (size_t i = 0; i < v.vertices(); ++i) {
        double q[3];
        vtx(v, i, q);
        assert_true(q[2] <= h + gx * q[0] + gy * q[1] + 1e-4);
      }
      print_message("  lid off the plane by at most %.2e mm, rim z %.2f .. %.2f\n", worst, zlo, zhi);
      assert_true(worst < 1e-4);
      const double rise = std::tan(4.0 * kPi / 180) * p.max_radius_mm;
      assert_true(zhi > h + 0.95 * rise && zlo < h - 0.95 * rise);
      // The ground ring: the tail of the scanned triangles, on the plane, facing
      // down, and the same area as the untilted ring / cos(tilt).
      const Mesh &s = p.scanned;
      assert_true(p.ground_triangles == p0.ground_triangles && p.ground_triangles > 0);
      assert_memory_equal(s.xyz.data(), v.xyz.data(), (v.xyz.size() - 3) * sizeof(float));
      double area = 0, area0 = 0;
      for (size_t t = s.triangles() - p.ground_triangles; t < s.triangles(); ++t) {
        double q[3][3], q0[3][3];
        for (int e = 0; e < 3; ++e) {
          vtx(s, s.tri[3 * t + e], q[e]);
          vtx(p0.scanned, p0.scanned.tri[3 * t + e], q0[e]);
          assert_true(std::fabs(q[e][2] - (h + gx * q[e][0] + gy * q[e][1])) < 1e-4);
        }
        const double ux = q[1][0] - q[0][0], uy = q[1][1] - q[0][1], uz = q[1][2] - q[0][2];
        const double wx = q[2][0] - q[0][0], wy = q[2][1] - q[0][1], wz = q[2][2] - q[0][2];
        const double nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
        assert_true(nz < 0);
        area += 0.5 * std::sqrt(nx * nx + ny * ny + nz * nz);
        area0 += 0.5 * std::fabs((q0[1][0] - q0[0][0]) * (q0[2][1] - q0[0][1]) -
                                 (q0[1][1] - q0[0][1]) * (q0[2][0] - q0[0][0]));
      }
      assert_true(rel(area * std::cos(4.0 * kPi / 180), area0) < 1e-6);
    }
}

void test_depth_override(void **) {
  PitOptions o;
  o.depth_mm = 600.0;
  const Pit p = make_pit(Family::Cylinder, true, 4, o);
  check_watertight(p.void_closed);
  check_scanned(p);
  const double R = jnum(p.params_json, "radius_mm"), N = jnum(p.params_json, "angles");
  assert_true(p.rim_z_mm == 600.0 && jnum(p.params_json, "depth_mm") == 600.0);
  // Same radius as without the override (the draws are unchanged).
  assert_true(R == jnum(make_pit(Family::Cylinder, true, 4).params_json, "radius_mm"));
  const double exact = 0.5 * N * R * R * std::sin(2 * kPi / N) * 600.0;
  print_message("600 mm cylinder: V %.3f polygon prism %.3f rel %.2e\n", p.volume_mm3, exact,
                rel(p.volume_mm3, exact));
  assert_true(rel(p.volume_mm3, exact) < 1e-9);
  bool threw = false;
  try {
    make_pit(Family::Tapered, true, 4, o);
  } catch (const std::invalid_argument &) {
    threw = true;
  }
  assert_true(threw);
}

void test_names(void **) {
  Family f;
  assert_true(pv::sim::family_from_name("hand_dug", &f) && f == Family::HandDug);
  assert_true(pv::sim::family_from_name("HandDug", &f) && f == Family::HandDug);
  assert_true(pv::sim::family_from_name("deep-narrow", &f) && f == Family::DeepNarrow);
  assert_false(pv::sim::family_from_name("trench", &f));
  assert_string_equal(pv::sim::family_name(Family::Cylinder), "cylinder");
}

}  // namespace

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_names),
      cmocka_unit_test(test_cylinder_exact_polygon),
      cmocka_unit_test(test_tapered_frustum),
      cmocka_unit_test(test_elliptical),
      cmocka_unit_test(test_volume_below),
      cmocka_unit_test(test_all_families),
      cmocka_unit_test(test_family_ranges),
      cmocka_unit_test(test_deterministic),
      cmocka_unit_test(test_volume_origin_independent),
      cmocka_unit_test(test_default_options_identical),
      cmocka_unit_test(test_stone),
      cmocka_unit_test(test_tilted_ground),
      cmocka_unit_test(test_depth_override),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
