// USB frame format v1: CRC-32C against published check values, the byte
// layout of an encoded frame, and parse/encode round trips with errors.
#include <cstring>
#include <vector>

#include "pitvol/usb_frame.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

void crc32c_matches_the_standard_check_values(void **) {
  // RFC 3720 (iSCSI) B.4 and the common "123456789" check value.
  assert_int_equal(pv_crc32c(0, "123456789", 9), 0xE3069283u);
  const std::vector<uint8_t> zeros(32, 0x00), ones(32, 0xff);
  assert_int_equal(pv_crc32c(0, zeros.data(), 32), 0x8A9136AAu);
  assert_int_equal(pv_crc32c(0, ones.data(), 32), 0x62A8AB43u);
  std::vector<uint8_t> inc(32);
  for (int i = 0; i < 32; ++i) inc[size_t(i)] = uint8_t(i);
  assert_int_equal(pv_crc32c(0, inc.data(), 32), 0x46DD794Eu);
  // Chaining over a split equals one pass.
  assert_int_equal(pv_crc32c(pv_crc32c(0, "1234", 4), "56789", 5), 0xE3069283u);
}

void encoded_bytes_follow_the_documented_layout(void **) {
  const float pts[6] = {1.0f, -2.5f, 300.25f, 0.0f, 1e-3f, -7.0f};
  pv_usb_frame_header_t h{PV_USB_FRAME_VERSION, PV_USB_FLAG_END_OF_SCAN, 2, 0x01020304u,
                          0x1122334455667788ull};
  uint8_t buf[PV_USB_FRAME_BYTES(2)];
  assert_int_equal(pv_usb_frame_encode(buf, sizeof buf, &h, pts), 48);
  const uint8_t head[20] = {'P', 'V', 'F', '1', 1, 1, 2, 0, 4, 3, 2, 1,
                            0x88, 0x77, 0x66, 0x55, 0x44, 0x33, 0x22, 0x11};
  assert_memory_equal(buf, head, 20);
  // 1.0f = 0x3F800000, little endian.
  const uint8_t one[4] = {0x00, 0x00, 0x80, 0x3f};
  assert_memory_equal(buf + 20, one, 4);
  const uint32_t crc = pv_crc32c(0, buf, 44);
  assert_int_equal(buf[44] | buf[45] << 8 | buf[46] << 16 | uint32_t(buf[47]) << 24, crc);
  assert_true(pv_usb_frame_crc_ok(buf, 2));
}

void round_trip_and_corruption(void **) {
  std::vector<float> pts(3 * PV_USB_MAX_POINTS);
  for (size_t i = 0; i < pts.size(); ++i) pts[i] = float(i) * 0.25f - 1000.0f;
  std::vector<uint8_t> buf(PV_USB_MAX_FRAME_BYTES);
  pv_usb_frame_header_t h{PV_USB_FRAME_VERSION, 0, uint16_t(PV_USB_MAX_POINTS), 7, 123456};
  assert_int_equal(pv_usb_frame_encode(buf.data(), buf.size(), &h, pts.data()), PV_USB_MAX_FRAME_BYTES);
  pv_usb_frame_header_t g;
  assert_int_equal(pv_usb_frame_parse_header(buf.data(), buf.size(), &g), PV_USB_PARSE_OK);
  assert_int_equal(g.point_count, PV_USB_MAX_POINTS);
  assert_int_equal(g.sequence, 7);
  assert_true(g.timestamp_us == 123456);
  assert_true(pv_usb_frame_crc_ok(buf.data(), g.point_count));
  float p[3];
  pv_usb_frame_point(buf.data(), 4095, p);
  assert_true(p[0] == pts[3 * 4095] && p[2] == pts[3 * 4095 + 2]);
  // One flipped bit anywhere fails the CRC.
  for (size_t at : {size_t(0) + 9, size_t(20), buf.size() / 2, buf.size() - 1}) {
    buf[at] ^= 0x10;
    assert_false(pv_usb_frame_crc_ok(buf.data(), g.point_count));
    buf[at] ^= 0x10;
  }
}

void bad_headers_are_named(void **) {
  uint8_t buf[PV_USB_FRAME_BYTES(0)];
  pv_usb_frame_header_t h{PV_USB_FRAME_VERSION, 0, 0, 0, 0};
  assert_int_equal(pv_usb_frame_encode(buf, sizeof buf, &h, nullptr), 24);
  pv_usb_frame_header_t g;
  assert_int_equal(pv_usb_frame_parse_header(buf, 19, &g), PV_USB_PARSE_NEED_MORE);
  buf[0] ^= 1;
  assert_int_equal(pv_usb_frame_parse_header(buf, 24, &g), PV_USB_PARSE_BAD_MAGIC);
  buf[0] ^= 1;
  buf[4] = 2;
  assert_int_equal(pv_usb_frame_parse_header(buf, 24, &g), PV_USB_PARSE_BAD_VERSION);
  buf[4] = 1;
  buf[5] = 0x80;
  assert_int_equal(pv_usb_frame_parse_header(buf, 24, &g), PV_USB_PARSE_BAD_FLAGS);
  buf[5] = 0;
  buf[6] = 0x01;
  buf[7] = 0x10;  // 4097
  assert_int_equal(pv_usb_frame_parse_header(buf, 24, &g), PV_USB_PARSE_BAD_COUNT);
  // The encoder refuses what it cannot write.
  h.point_count = PV_USB_MAX_POINTS + 1;
  assert_int_equal(pv_usb_frame_encode(buf, sizeof buf, &h, nullptr), 0);
  h.point_count = 1;
  assert_int_equal(pv_usb_frame_encode(buf, sizeof buf, &h, nullptr), 0);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(crc32c_matches_the_standard_check_values),
      cmocka_unit_test(encoded_bytes_follow_the_documented_layout),
      cmocka_unit_test(round_trip_and_corruption),
      cmocka_unit_test(bad_headers_are_named),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
