// The display driver (PSF2 fonts, canvas, framebuffer conversion, PNG
// backend read back with libpng) and the buttons driver (pipe, evdev).
#include <fcntl.h>
#include <linux/input.h>
#include <png.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "pitvol/board_fonts.h"
#include "pitvol/canvas.h"
#include "pitvol/display.h"
#include "pitvol/input.h"

#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

std::string slurp(const std::string &path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void embedded_fonts_parse(void **) {
  pv_font_t f;
  assert_int_equal(pv_font_parse_psf2(&f, pv_font_10x20, pv_font_10x20_bytes), PV_DISPLAY_OK);
  assert_int_equal(f.width_px, 10u);
  assert_int_equal(f.height_px, 20u);
  assert_int_equal(pv_font_parse_psf2(&f, pv_font_16x32, pv_font_16x32_bytes), PV_DISPLAY_OK);
  assert_int_equal(f.width_px, 16u);
  assert_int_equal(f.height_px, 32u);
  // Distinct glyphs for what the screens use (degree, cubed, plus-minus).
  assert_int_not_equal(f.latin1['A'], f.latin1['0']);
  for (int cp : {0xB0, 0xB3, 0xB1, int('~'), int('-')}) assert_int_not_equal(f.latin1[cp], f.latin1['?']);
}

// A two-glyph PSF2 (4x2) whose Unicode table maps glyph 1 to 'A', '0', '?'.
std::vector<uint8_t> tiny_font() {
  const uint32_t hdr[8] = {0x864ab572u, 0, 32, 1, 2, 2, 2, 4};
  const uint8_t glyphs[] = {0x00, 0x00, 0xF0, 0x90};
  const uint8_t table[] = {0xFF, 'A', '0', '?', 0xFF};
  std::vector<uint8_t> v(sizeof hdr + sizeof glyphs + sizeof table);
  std::memcpy(v.data(), hdr, sizeof hdr);
  std::memcpy(v.data() + sizeof hdr, glyphs, sizeof glyphs);
  std::memcpy(v.data() + sizeof hdr + sizeof glyphs, table, sizeof table);
  return v;
}

void psf2_parser_maps_and_rejects(void **) {
  std::vector<uint8_t> v = tiny_font();
  pv_font_t f;
  assert_int_equal(pv_font_parse_psf2(&f, v.data(), v.size()), PV_DISPLAY_OK);
  assert_int_equal(f.latin1['A'], 1);
  assert_int_equal(f.latin1['Z'], 1);  // unmapped -> the '?' glyph
  // Each fault of a font file, by its code, and a message that says what to do.
  assert_int_equal(pv_font_parse_psf2(&f, v.data(), 35), PV_DISPLAY_ERR_FONT_TRUNCATED);
  assert_non_null(std::strstr(pv_display_status_message(PV_DISPLAY_ERR_FONT_TRUNCATED), "truncated"));
  assert_int_equal(pv_font_parse_psf2(&f, v.data(), 31), PV_DISPLAY_ERR_FONT_FORMAT);
  assert_int_equal(pv_font_parse_psf2(nullptr, v.data(), v.size()), PV_DISPLAY_ERR_INVALID_ARGUMENT);
  {
    std::vector<uint8_t> bad = v;
    bad[28] = 65;  // 65 px wide: more than a console font has
    assert_int_equal(pv_font_parse_psf2(&f, bad.data(), bad.size()), PV_DISPLAY_ERR_FONT_HEADER);
    bad = v;
    bad[32 + 4 + 1] = 0xC3;  // 'A' in the Unicode table becomes a cut-off UTF-8 sequence
    bad[32 + 4 + 2] = 'x';
    assert_int_equal(pv_font_parse_psf2(&f, bad.data(), bad.size()), PV_DISPLAY_ERR_FONT_UNICODE);
    bad = v;
    bad[32 + 4 + 3] = 'B';  // no '?' glyph left
    assert_int_equal(pv_font_parse_psf2(&f, bad.data(), bad.size()), PV_DISPLAY_ERR_FONT_GLYPHS);
  }
  v[0] = 0x36;  // PSF1 magic
  assert_int_equal(pv_font_parse_psf2(&f, v.data(), v.size()), PV_DISPLAY_ERR_FONT_FORMAT);
  assert_non_null(std::strstr(pv_display_status_message(PV_DISPLAY_ERR_FONT_FORMAT), "gunzip"));
  assert_string_equal(pv_display_status_name(PV_DISPLAY_ERR_FONT_FORMAT), "PV_DISPLAY_ERR_FONT_FORMAT");
}

void canvas_init_refuses_short_memory(void **) {
  pv_canvas_t c{};
  std::vector<uint8_t> mem(pv_canvas_bytes(8, 8, 16));
  assert_int_equal(pv_canvas_init(&c, 8, 8, 16, mem.data(), mem.size() - 1), PV_DISPLAY_ERR_CANVAS_MEMORY);
  assert_int_equal(pv_canvas_init(&c, 0, 8, 16, mem.data(), mem.size()), PV_DISPLAY_ERR_INVALID_ARGUMENT);
  assert_int_equal(pv_canvas_init(&c, 8, 8, 16, mem.data(), mem.size()), PV_DISPLAY_OK);
}

// Every code of the display, input, ui and board ranges has a name and a
// message, and lies in its module's range (docs/errors.md).
void status_names_and_messages(void **) {
  for (int code = PV_DISPLAY_ERR_INVALID_ARGUMENT; code <= PV_DISPLAY_ERR_FONT_GLYPHS; ++code) {
    const auto st = static_cast<pv_display_status_t>(code);
    assert_non_null(std::strstr(pv_display_status_name(st), "PV_DISPLAY_ERR_"));
    assert_string_not_equal(pv_display_status_name(st), "PV_DISPLAY_ERR_UNKNOWN");
    assert_string_not_equal(pv_display_status_message(st), "unknown display status");
  }
  for (int code = PV_INPUT_ERR_INVALID_ARGUMENT; code <= PV_INPUT_ERR_GONE; ++code) {
    const auto st = static_cast<pv_input_status_t>(code);
    assert_string_not_equal(pv_input_status_name(st), "PV_INPUT_ERR_UNKNOWN");
    assert_string_not_equal(pv_input_status_message(st), "unknown input status");
  }
  assert_string_equal(pv_display_status_name(static_cast<pv_display_status_t>(749)),
                      "PV_DISPLAY_ERR_UNKNOWN");
}

struct Canvas {
  std::vector<uint8_t> mem;
  pv_canvas_t c{};
  Canvas(uint16_t w, uint16_t h, size_t text = 1024) : mem(pv_canvas_bytes(w, h, text)) {
    assert_int_equal(pv_canvas_init(&c, w, h, text, mem.data(), mem.size()), PV_DISPLAY_OK);
  }
};

void canvas_text_draws_in_its_box_and_logs(void **) {
  Canvas cv(64, 48);
  std::vector<uint8_t> v = tiny_font();
  pv_font_t f;
  assert_int_equal(pv_font_parse_psf2(&f, v.data(), v.size()), PV_DISPLAY_OK);
  const int w = pv_canvas_text(&cv.c, &f, 2, 10, 20, PV_COLOR_RED, "AA");
  assert_int_equal(w, 16);
  int inside = 0, outside = 0;
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      const bool box = x >= 10 && x < 26 && y >= 20 && y < 24;
      const uint8_t p = cv.c.px[y * 64 + x];
      if (p == PV_COLOR_RED) (box ? inside : outside)++;
    }
  }
  // Glyph 1 has 4 + 2 set pixels, scaled 2x2, twice.
  assert_int_equal(inside, 2 * 6 * 4);
  assert_int_equal(outside, 0);
  pv_canvas_note(&cv.c, "bar %d", 3);
  assert_string_equal(cv.c.text, "text 10 20 4|AA\nbar 3\n");
  // Clipping: text running off the canvas does not write outside it.
  pv_canvas_text(&cv.c, &f, 8, 60, 44, PV_COLOR_BLACK, "AAAA");
  // A full log says so instead of cutting silently.
  Canvas small(8, 8, 16);
  pv_canvas_note(&small.c, "a fairly long line of text");
  assert_true(small.c.text_truncated);
}

void framebuffer_layouts(void **) {
  Canvas cv(4, 2);
  pv_canvas_fill(&cv.c, 1, 0, 1, 1, PV_COLOR_RED);
  pv_canvas_fill(&cv.c, 2, 0, 1, 1, PV_COLOR_BLACK);
  const pv_fb_format_t rgb565{16, 11, 5, 5, 6, 0, 5};
  std::vector<uint8_t> fb(2 * 16, 0xAA);
  assert_int_equal(pv_fb_blit(&cv.c, &rgb565, fb.data(), 16), PV_DISPLAY_OK);
  uint16_t p[3];
  std::memcpy(p, fb.data(), sizeof p);
  assert_int_equal(p[0], 0xFFFF);
  assert_int_equal(p[1], ((0xD0 >> 3) << 11) | ((0x10 >> 2) << 5) | (0x10 >> 3));
  assert_int_equal(p[2], 0x0000);
  assert_int_equal(fb[8], 0xAA);  // the row's padding is left alone
  const pv_fb_format_t xrgb{32, 16, 8, 8, 8, 0, 8};
  std::vector<uint8_t> fb32(2 * 16);
  assert_int_equal(pv_fb_blit(&cv.c, &xrgb, fb32.data(), 16), PV_DISPLAY_OK);
  uint32_t q[2];
  std::memcpy(q, fb32.data(), sizeof q);
  assert_int_equal(q[0], 0xFFFFFFu);
  assert_int_equal(q[1], 0xD01010u);
  const pv_fb_format_t bad{24, 16, 8, 8, 8, 0, 8};
  assert_int_equal(pv_fb_blit(&cv.c, &bad, fb32.data(), 16), PV_DISPLAY_ERR_FB_FORMAT);
  assert_int_equal(pv_fb_blit(&cv.c, &xrgb, fb32.data(), 15), PV_DISPLAY_ERR_INVALID_ARGUMENT);
}

void png_backend_writes_image_text_and_log(void **) {
  char dir[] = "/tmp/pv_png_testXXXXXX";
  assert_non_null(mkdtemp(dir));
  const std::string d = dir;
  pv_display_t *disp = nullptr;
  char err[256];
  assert_int_equal(pv_display_open(&disp, ("png:" + d).c_str(), 32, 24, err, sizeof err), PV_DISPLAY_OK);
  Canvas cv(32, 24);
  pv_canvas_fill(&cv.c, 0, 0, 32, 12, PV_COLOR_GREEN);
  pv_canvas_note(&cv.c, "hello");
  assert_int_equal(pv_display_present(disp, &cv.c, "result", err, sizeof err), PV_DISPLAY_OK);
  pv_canvas_clear(&cv.c, PV_COLOR_WHITE);
  pv_canvas_note(&cv.c, "again");
  assert_int_equal(pv_display_present(disp, &cv.c, "idle", err, sizeof err), PV_DISPLAY_OK);
  Canvas wrong(16, 16);
  assert_int_equal(pv_display_present(disp, &wrong.c, "x", err, sizeof err),
                   PV_DISPLAY_ERR_INVALID_ARGUMENT);
  // A screen whose PNG cannot be written (its directory does not exist):
  // the path in err, and screens.log keeps only the screens shown.
  assert_int_equal(pv_display_present(disp, &cv.c, "missing/idle", err, sizeof err),
                   PV_DISPLAY_ERR_WRITE);
  assert_non_null(std::strstr(err, "missing/idle.png"));
  const std::string long_name(5000, 'x');
  assert_int_equal(pv_display_present(disp, &cv.c, long_name.c_str(), err, sizeof err),
                   PV_DISPLAY_ERR_PATH_TOO_LONG);
  pv_display_close(disp);

  assert_string_equal(slurp(d + "/result.txt").c_str(), "hello\n");
  assert_string_equal(slurp(d + "/screens.log").c_str(), "=== 1 result\nhello\n=== 2 idle\nagain\n");
  // Read the PNG back: green top half, white bottom half.
  png_image img;
  std::memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  assert_true(png_image_begin_read_from_file(&img, (d + "/result.png").c_str()));
  img.format = PNG_FORMAT_RGB;
  assert_int_equal(img.width, 32u);
  assert_int_equal(img.height, 24u);
  std::vector<uint8_t> rgb(PNG_IMAGE_SIZE(img));
  assert_true(png_image_finish_read(&img, nullptr, rgb.data(), 0, nullptr));
  assert_int_equal(rgb[0], 0x00);
  assert_int_equal(rgb[1], 0xA0);
  assert_int_equal(rgb[2], 0x40);
  const size_t bottom = (20 * 32 + 5) * 3;
  assert_int_equal(rgb[bottom], 0xFF);
  assert_int_equal(rgb[bottom + 1], 0xFF);
  std::system(("rm -rf '" + d + "'").c_str());
}

void display_spec_errors_say_what_to_do(void **) {
  pv_display_t *disp = nullptr;
  char err[256];
  assert_int_equal(pv_display_open(&disp, "vga:0", 320, 240, err, sizeof err), PV_DISPLAY_ERR_SPEC);
  assert_non_null(std::strstr(err, "fbdev:/dev/fbN"));
  assert_non_null(std::strstr(pv_display_status_message(PV_DISPLAY_ERR_SPEC), "png:DIR"));
  assert_int_equal(pv_display_open(&disp, "fbdev:/nonexistent/fb9", 320, 240, err, sizeof err),
                   PV_DISPLAY_ERR_OPEN);
  assert_non_null(std::strstr(err, "/nonexistent/fb9"));
  // A device that opens but is no framebuffer.
  assert_int_equal(pv_display_open(&disp, "fbdev:/dev/null", 320, 240, err, sizeof err),
                   PV_DISPLAY_ERR_FB_DEVICE);
  assert_non_null(std::strstr(err, "/dev/null is not a framebuffer"));
  assert_int_equal(pv_display_open(&disp, "png:", 320, 240, err, sizeof err), PV_DISPLAY_ERR_SPEC);
  assert_int_equal(pv_display_open(&disp, "png:x", 0, 240, err, sizeof err),
                   PV_DISPLAY_ERR_INVALID_ARGUMENT);
  // A screen directory that cannot be made: its parent is a file.
  char file[] = "/tmp/pv_png_fileXXXXXX";
  const int fd = mkstemp(file);
  assert_true(fd >= 0);
  close(fd);
  assert_int_equal(pv_display_open(&disp, ("png:" + std::string(file) + "/screens").c_str(), 320,
                                   240, err, sizeof err),
                   PV_DISPLAY_ERR_OPEN);
  assert_non_null(std::strstr(err, "cannot create the screen directory"));
  unlink(file);
}

void pipe_buttons(void **) {
  const std::string path = "/tmp/pv_input_test_" + std::to_string(getpid());
  pv_input_t *in = nullptr;
  char err[256];
  assert_int_equal(pv_input_open(&in, ("pipe:" + path).c_str(), err, sizeof err), PV_INPUT_OK);
  const int w = open(path.c_str(), O_WRONLY | O_NONBLOCK);
  assert_true(w >= 0);
  const char first[] = "start\nbogus\nenter\nba";
  assert_int_equal(write(w, first, sizeof first - 1), ssize_t(sizeof first - 1));
  pv_key_t keys[8];
  size_t n = 99;
  assert_int_equal(pv_input_read(in, keys, 8, &n, err, sizeof err), PV_INPUT_OK);
  assert_int_equal(n, 2);
  assert_int_equal(keys[0], PV_KEY_START_STOP);
  assert_int_equal(keys[1], PV_KEY_ENTER);
  assert_int_equal(write(w, "ck\r\n", 4), 4);  // the rest of "back", CRLF
  close(w);  // the last outside writer leaves: no end-of-file for the board
  assert_int_equal(pv_input_read(in, keys, 8, &n, err, sizeof err), PV_INPUT_OK);
  assert_int_equal(n, 1);
  assert_int_equal(keys[0], PV_KEY_BACK);
  assert_int_equal(pv_input_read(in, keys, 8, &n, err, sizeof err), PV_INPUT_OK);
  assert_int_equal(n, 0);
  pv_input_close(in);
  unlink(path.c_str());
}

void evdev_presses_only(void **) {
  // The evdev backend reads struct input_event records; a FIFO carries them.
  const std::string path = "/tmp/pv_evdev_test_" + std::to_string(getpid());
  assert_int_equal(mkfifo(path.c_str(), 0600), 0);
  pv_input_t *in = nullptr;
  char err[256];
  assert_int_equal(pv_input_open(&in, ("evdev:" + path).c_str(), err, sizeof err), PV_INPUT_OK);
  const int w = open(path.c_str(), O_WRONLY | O_NONBLOCK);
  assert_true(w >= 0);
  auto ev = [](uint16_t type, uint16_t code, int32_t value) {
    input_event e{};
    e.type = type;
    e.code = code;
    e.value = value;
    return e;
  };
  const input_event evs[] = {
      ev(EV_KEY, KEY_ENTER, 1), ev(EV_SYN, SYN_REPORT, 0), ev(EV_KEY, KEY_ENTER, 2),  // repeat
      ev(EV_KEY, KEY_ENTER, 0),  // release
      ev(EV_KEY, KEY_A, 1),      // not a button
      ev(EV_KEY, KEY_ESC, 1),    ev(EV_KEY, KEY_RECORD, 1),
  };
  assert_int_equal(write(w, evs, sizeof evs), ssize_t(sizeof evs));
  pv_key_t keys[8];
  size_t n = 0;
  assert_int_equal(pv_input_read(in, keys, 8, &n, err, sizeof err), PV_INPUT_OK);
  assert_int_equal(n, 3);
  assert_int_equal(keys[0], PV_KEY_ENTER);
  assert_int_equal(keys[1], PV_KEY_BACK);
  assert_int_equal(keys[2], PV_KEY_START_STOP);
  close(w);
  assert_int_equal(pv_input_read(in, keys, 8, &n, err, sizeof err), PV_INPUT_ERR_GONE);
  assert_int_equal(n, 0);
  assert_non_null(std::strstr(err, "went away"));
  pv_input_close(in);
  unlink(path.c_str());
}

void input_spec_errors(void **) {
  pv_input_t *in = nullptr;
  char err[256];
  assert_int_equal(pv_input_open(&in, "usb:1", err, sizeof err), PV_INPUT_ERR_SPEC);
  assert_non_null(std::strstr(err, "pipe:PATH"));
  assert_null(in);
  assert_int_equal(pv_input_open(&in, "evdev:/nonexistent/event9", err, sizeof err), PV_INPUT_ERR_OPEN);
  assert_non_null(std::strstr(err, "/nonexistent/event9"));
  assert_int_equal(pv_input_open(&in, "pipe:/nonexistent/buttons", err, sizeof err), PV_INPUT_ERR_PIPE);
  assert_non_null(std::strstr(err, "/nonexistent/buttons"));
  assert_int_equal(pv_input_open(&in, nullptr, err, sizeof err), PV_INPUT_ERR_INVALID_ARGUMENT);
  assert_non_null(std::strstr(pv_input_status_message(PV_INPUT_ERR_OPEN), "permissions"));
  // "none": no buttons, nothing to read.
  assert_int_equal(pv_input_open(&in, "none", err, sizeof err), PV_INPUT_OK);
  pv_key_t keys[2];
  size_t n = 5;
  assert_int_equal(pv_input_read(in, keys, 2, &n, err, sizeof err), PV_INPUT_OK);
  assert_int_equal(n, 0);
  pv_input_close(in);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(embedded_fonts_parse),
      cmocka_unit_test(psf2_parser_maps_and_rejects),
      cmocka_unit_test(canvas_init_refuses_short_memory),
      cmocka_unit_test(status_names_and_messages),
      cmocka_unit_test(canvas_text_draws_in_its_box_and_logs),
      cmocka_unit_test(framebuffer_layouts),
      cmocka_unit_test(png_backend_writes_image_text_and_log),
      cmocka_unit_test(display_spec_errors_say_what_to_do),
      cmocka_unit_test(pipe_buttons),
      cmocka_unit_test(evdev_presses_only),
      cmocka_unit_test(input_spec_errors),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
