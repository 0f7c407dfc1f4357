// See ply_points.h.
#include "ply_points.h"

#include <stdlib.h>
#include <string.h>

namespace pv::firmware {

namespace {

// Bytes of a PLY scalar type, 0 if unknown.
size_t type_size(const char *t) {
  static const struct { const char *name; size_t bytes; } kTypes[] = {
      {"char", 1},   {"uchar", 1},  {"int8", 1},   {"uint8", 1},   {"short", 2},
      {"ushort", 2}, {"int16", 2},  {"uint16", 2}, {"int", 4},     {"uint", 4},
      {"int32", 4},  {"uint32", 4}, {"float", 4},  {"float32", 4}, {"double", 8},
      {"float64", 8}};
  for (const auto &k : kTypes)
    if (strcmp(t, k.name) == 0) return k.bytes;
  return 0;
}

double read_le(const unsigned char *p, bool is_double) {
  if (is_double) {
    uint64_t u = 0;
    for (int i = 7; i >= 0; --i) u = (u << 8) | p[i];
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
  }
  uint32_t u = 0;
  for (int i = 3; i >= 0; --i) u = (u << 8) | p[i];
  float f;
  memcpy(&f, &u, sizeof f);
  return f;
}

}  // namespace

PlyPoints::~PlyPoints() {
  if (f_ != nullptr) fclose(f_);
}

bool PlyPoints::fail(const char *why) {
  if (error_ == nullptr) error_ = why;
  return false;
}

bool PlyPoints::open(const char *path) {
  if (f_ != nullptr) fclose(f_);
  f_ = fopen(path, "rb");
  if (f_ == nullptr) return fail("cannot open the file");
  char line[256];
  if (fgets(line, sizeof line, f_) == nullptr || strncmp(line, "ply", 3) != 0)
    return fail("not a PLY file");
  bool in_vertex = false, seen_vertex = false, little = false;
  bool have[3] = {false, false, false};
  while (fgets(line, sizeof line, f_) != nullptr) {
    if (strncmp(line, "end_header", 10) == 0) {
      if (!little) return fail("only binary_little_endian PLY is supported here");
      if (!seen_vertex || !have[0] || !have[1] || !have[2])
        return fail("no vertex element with x, y and z");
      return true;
    }
    char a[64], b[64], c[64];
    const int k = sscanf(line, "%63s %63s %63s", a, b, c);
    if (k >= 2 && strcmp(a, "format") == 0) {
      little = strcmp(b, "binary_little_endian") == 0;
    } else if (k == 3 && strcmp(a, "element") == 0) {
      if (seen_vertex) {
        in_vertex = false;  // later elements come after the vertices: ignored
      } else if (strcmp(b, "vertex") == 0) {
        in_vertex = seen_vertex = true;
        remaining_ = strtoull(c, nullptr, 10);
      } else {
        return fail("the vertex element must come first");
      }
    } else if (k == 3 && strcmp(a, "property") == 0 && in_vertex) {
      const size_t bytes = type_size(b);
      if (bytes == 0) return fail("list or unknown property type in the vertex element");
      for (int axis = 0; axis < 3; ++axis) {
        if (strcmp(c, axis == 0 ? "x" : axis == 1 ? "y" : "z") != 0) continue;
        if (bytes != 4 && bytes != 8) return fail("x, y, z must be float or double");
        if (bytes == 4 && strcmp(b, "float") != 0 && strcmp(b, "float32") != 0)
          return fail("x, y, z must be float or double");
        offset_[axis] = stride_;
        is_double_[axis] = bytes == 8;
        have[axis] = true;
      }
      stride_ += bytes;
    }
  }
  return fail("no end_header");
}

size_t PlyPoints::read(pv_point_t *out, size_t cap) {
  if (f_ == nullptr || error_ != nullptr || stride_ == 0) return 0;
  const size_t per_buf = sizeof buf_ / stride_;
  size_t want = cap < per_buf ? cap : per_buf;
  if (remaining_ < want) want = static_cast<size_t>(remaining_);
  if (want == 0) return 0;
  if (fread(buf_, stride_, want, f_) != want) {
    fail("the file ends before its last vertex");
    return 0;
  }
  for (size_t i = 0; i < want; ++i) {
    const unsigned char *p = buf_ + i * stride_;
    out[i].x_mm = static_cast<float>(read_le(p + offset_[0], is_double_[0]));
    out[i].y_mm = static_cast<float>(read_le(p + offset_[1], is_double_[1]));
    out[i].z_mm = static_cast<float>(read_le(p + offset_[2], is_double_[2]));
  }
  remaining_ -= want;
  return want;
}

}  // namespace pv::firmware
