#include "grid25.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

namespace pv::peers {

namespace {

constexpr double kPi = 3.14159265358979323846;

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const size_t k = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + long(k), v.end());
  return v[k];
}

struct Outline {
  double cx = 0, cy = 0;
  std::vector<double> r;  // per sector, the radius at its centre angle
  uint32_t empty = 0;
  double radius_at(double x, double y) const {
    const size_t n = r.size();
    double a = std::atan2(y - cy, x - cx) / (2 * kPi) * double(n) - 0.5;
    if (a < 0) a += double(n);
    const size_t i = size_t(a) % n;
    const double f = a - std::floor(a);
    return (1 - f) * r[i] + f * r[(i + 1) % n];
  }
};

bool find_outline(const std::vector<LevelledPoint> &pts, double rim_mm, const Grid25Params &p,
                  Outline *o, std::string *err) {
  std::vector<double> xs, ys;
  for (const LevelledPoint &q : pts) {
    if (q.z_mm < 0.5 * rim_mm) {
      xs.push_back(q.x_mm);
      ys.push_back(q.y_mm);
    }
  }
  if (xs.size() < 100) {
    *err = "fewer than 100 points below half the depth: no pit axis";
    return false;
  }
  o->cx = median(xs);
  o->cy = median(ys);
  const uint32_t n = p.sectors;
  // The three largest radii per sector, largest first.
  std::vector<double> top(3 * size_t(n), -1.0);
  const double z_lo = rim_mm - p.band_depth_mm, z_hi = rim_mm - p.band_top_mm;
  for (const LevelledPoint &q : pts) {
    if (q.z_mm < z_lo || q.z_mm > z_hi) continue;
    const double dx = q.x_mm - o->cx, dy = q.y_mm - o->cy;
    double a = std::atan2(dy, dx) / (2 * kPi);
    if (a < 0) a += 1.0;
    const size_t s = std::min<size_t>(size_t(a * n), n - 1);
    double r = std::hypot(dx, dy);
    double *t = &top[3 * s];
    for (int k = 0; k < 3; ++k) {
      if (r > t[k]) std::swap(r, t[k]);
    }
  }
  o->r.assign(n, -1.0);
  for (uint32_t s = 0; s < n; ++s) {
    if (top[3 * s + 2] > 0) o->r[s] = top[3 * s + 2];
  }
  o->empty = uint32_t(std::count(o->r.begin(), o->r.end(), -1.0));
  if (o->empty * 2 > n) {
    *err = "the top of the wall (10 mm below the rim) is seen in fewer than half the directions";
    return false;
  }
  // Empty sectors: linear between the nearest seen sectors on either side.
  std::vector<double> seen = o->r;
  for (uint32_t s = 0; s < n; ++s) {
    if (seen[s] > 0) continue;
    uint32_t a = 1, b = 1;
    while (seen[(s + n - a) % n] <= 0) ++a;
    while (seen[(s + b) % n] <= 0) ++b;
    o->r[s] = (double(b) * seen[(s + n - a) % n] + double(a) * seen[(s + b) % n]) / double(a + b);
  }
  return true;
}

}  // namespace

Grid25Result grid25_volume(const std::vector<LevelledPoint> &pts, double rim_mm,
                           const Grid25Params &p) {
  Grid25Result res;
  if (!(rim_mm > 0) || !(p.cell_mm > 0) || p.sectors < 8) {
    res.error = "no rim height or invalid parameters";
    return res;
  }
  Outline o;
  if (!find_outline(pts, rim_mm, p, &o, &res.error)) return res;
  res.empty_sectors = o.empty;

  const double rmax = *std::max_element(o.r.begin(), o.r.end());
  const double c = p.cell_mm;
  const int64_t half = int64_t(std::ceil(rmax / c)) + 1;
  const int64_t w = 2 * half;  // cells per side; cell (i, j) spans x0 + i c ..
  const double x0 = o.cx - double(half) * c, y0 = o.cy - double(half) * c;
  const size_t cells = size_t(w * w);
  std::vector<uint8_t> inside(cells, 0);
  for (int64_t j = 0; j < w; ++j) {
    for (int64_t i = 0; i < w; ++i) {
      const double x = x0 + (double(i) + 0.5) * c, y = y0 + (double(j) + 0.5) * c;
      if (std::hypot(x - o.cx, y - o.cy) <= o.radius_at(x, y)) inside[size_t(j * w + i)] = 1;
    }
  }
  std::vector<double> sum(cells, 0.0);
  std::vector<uint32_t> cnt(cells, 0);
  for (const LevelledPoint &q : pts) {
    const double fi = std::floor((q.x_mm - x0) / c), fj = std::floor((q.y_mm - y0) / c);
    if (fi < 0 || fj < 0 || fi >= double(w) || fj >= double(w)) continue;
    const size_t k = size_t(int64_t(fj) * w + int64_t(fi));
    sum[k] += q.z_mm;
    ++cnt[k];
  }
  std::vector<double> h(cells, NAN);
  for (size_t k = 0; k < cells; ++k) {
    if (cnt[k] > 0) h[k] = sum[k] / cnt[k];
  }
  if (p.median) {
    std::vector<std::pair<size_t, float>> cz;
    for (const LevelledPoint &q : pts) {
      const double fi = std::floor((q.x_mm - x0) / c), fj = std::floor((q.y_mm - y0) / c);
      if (fi < 0 || fj < 0 || fi >= double(w) || fj >= double(w)) continue;
      cz.emplace_back(size_t(int64_t(fj) * w + int64_t(fi)), q.z_mm);
    }
    std::sort(cz.begin(), cz.end());
    for (size_t a = 0; a < cz.size();) {
      size_t b = a;
      while (b < cz.size() && cz[b].first == cz[a].first) ++b;
      const size_t m = b - a;
      h[cz[a].first] = m % 2 ? cz[a + m / 2].second : 0.5 * (double(cz[a + m / 2 - 1].second) + cz[a + m / 2].second);
      a = b;
    }
  }
  // Fill empty pit cells from filled 8-neighbours, one ring per pass (the
  // pass reads the previous pass's heights: the result does not depend on
  // the scan order).
  std::vector<size_t> todo;
  for (size_t k = 0; k < cells; ++k) {
    if (inside[k] && cnt[k] == 0) todo.push_back(k);
  }
  res.filled_cells = todo.size();
  std::vector<std::pair<size_t, double>> fills;
  while (!todo.empty()) {
    fills.clear();
    std::vector<size_t> rest;
    for (size_t k : todo) {
      const int64_t i = int64_t(k) % w, j = int64_t(k) / w;
      double s = 0;
      int m = 0;
      for (int64_t dj = -1; dj <= 1; ++dj) {
        for (int64_t di = -1; di <= 1; ++di) {
          const int64_t a = i + di, b = j + dj;
          if ((di == 0 && dj == 0) || a < 0 || b < 0 || a >= w || b >= w) continue;
          const double v = h[size_t(b * w + a)];
          if (!std::isnan(v)) {
            s += v;
            ++m;
          }
        }
      }
      if (m > 0) fills.emplace_back(k, s / m);
      else rest.push_back(k);
    }
    if (fills.empty()) {
      res.error = "a region inside the rim outline holds no points at all";
      return res;
    }
    for (const auto &f : fills) h[f.first] = f.second;
    todo.swap(rest);
  }
  double v_mm3 = 0;
  for (size_t k = 0; k < cells; ++k) {
    if (!inside[k]) continue;
    ++res.pit_cells;
    v_mm3 += (rim_mm - h[k]) * c * c;
  }
  res.outline_area_mm2 = double(res.pit_cells) * c * c;
  res.volume_cm3 = v_mm3 / 1000.0;
  res.ok = true;
  return res;
}

bool read_levelled_ply(const std::string &path, std::vector<LevelledPoint> *pts, double *rim_mm,
                       std::string *err) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *err = "cannot read " + path;
    return false;
  }
  std::string line;
  uint64_t n = 0;
  *rim_mm = -1;
  bool binary_le = false;
  int props = 0;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string a, b;
    ls >> a >> b;
    if (a == "format") binary_le = b == "binary_little_endian";
    else if (a == "comment" && b == "pitvol_rim_mm") ls >> *rim_mm;
    else if (a == "element" && b == "vertex") ls >> n;
    else if (a == "property") ++props;
    else if (a == "end_header") break;
  }
  if (!binary_le || props != 3 || n == 0) {
    *err = path + " is not a cloud written by pitvol measure --export-levelled";
    return false;
  }
  pts->resize(n);
  in.read(reinterpret_cast<char *>(pts->data()), std::streamsize(n * sizeof(LevelledPoint)));
  if (!in) {
    *err = path + " is truncated";
    return false;
  }
  return true;
}

}  // namespace pv::peers
