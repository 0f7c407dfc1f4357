// The USB frame header parser (drivers/usb/usb_frame.c) on arbitrary bytes.
//
// Invariants: fewer than 20 bytes is NEED_MORE, never a verdict; only the
// first 20 bytes decide; an accepted header has version 1, known flags and
// at most 4096 points, and encoding it again gives the same 20 bytes (the
// parser accepts nothing the encoder would not write).
#include <cstring>
#include <vector>

#include "fuzz_support.h"
#include "pitvol/usb_frame.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  pv_usb_frame_header_t h{};
  const pv_usb_parse_t r = pv_usb_frame_parse_header(data, size, &h);
  if (size < PV_USB_HEADER_BYTES) {
    PV_FUZZ_CHECK(r == PV_USB_PARSE_NEED_MORE, "%zu bytes gave %d", size, int(r));
    return 0;
  }
  PV_FUZZ_CHECK(r != PV_USB_PARSE_NEED_MORE, "NEED_MORE with %zu bytes", size);
  pv_usb_frame_header_t h20{};
  PV_FUZZ_CHECK(pv_usb_frame_parse_header(data, PV_USB_HEADER_BYTES, &h20) == r,
                "the bytes after the header changed the verdict");
  if (r != PV_USB_PARSE_OK) return 0;
  PV_FUZZ_CHECK(std::memcmp(&h, &h20, sizeof h) == 0, "header fields depend on later bytes");
  PV_FUZZ_CHECK(h.version == PV_USB_FRAME_VERSION, "version %u", unsigned(h.version));
  PV_FUZZ_CHECK((h.flags & ~PV_USB_FLAGS_KNOWN) == 0, "flags 0x%x", unsigned(h.flags));
  PV_FUZZ_CHECK(h.point_count <= PV_USB_MAX_POINTS, "point_count %u", unsigned(h.point_count));
  std::vector<float> pts(size_t(h.point_count) * 3, 0.0f);
  std::vector<uint8_t> out(PV_USB_FRAME_BYTES(h.point_count));
  const size_t n = pv_usb_frame_encode(out.data(), out.size(), &h, pts.data());
  PV_FUZZ_CHECK(n == out.size(), "encode wrote %zu of %zu bytes", n, out.size());
  PV_FUZZ_CHECK(std::memcmp(out.data(), data, PV_USB_HEADER_BYTES) == 0,
                "re-encoded header differs from the accepted bytes");
  return 0;
}
