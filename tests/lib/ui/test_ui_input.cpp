// Numbers, text and settings a user types (pitvol/user_input.h,
// pitvol/config_fields.h): each refusal by its code, with the sentence
// that names the value and the range; and counts as lib/ui prints them.
#include <cstring>
#include <string>

#include "pitvol/advice.h"
#include "pitvol/config_fields.h"
#include "pitvol/user_input.h"

#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

void decimals_by_their_fault(void **) {
  char err[160];
  double v = -1;
  assert_int_equal(pv_parse_decimal("1850", &v, err, sizeof err), PV_UI_OK);
  assert_true(v == 1850.0);
  assert_int_equal(pv_parse_decimal("-2.5e3", &v, err, sizeof err), PV_UI_OK);
  assert_true(v == -2500.0);
  assert_int_equal(pv_parse_decimal("", &v, err, sizeof err), PV_UI_ERR_NUMBER_MISSING);
  assert_int_equal(pv_parse_decimal(nullptr, &v, err, sizeof err), PV_UI_ERR_NUMBER_MISSING);
  assert_int_equal(pv_parse_decimal("1,5", &v, err, sizeof err), PV_UI_ERR_DECIMAL_COMMA);
  assert_non_null(std::strstr(err, "write decimals with a point"));
  for (const char *text : {"0x10", "inf", "nan", "1.2.3", "12 g", "e5", "1e", "-"}) {
    assert_int_equal(pv_parse_decimal(text, &v, err, sizeof err), PV_UI_ERR_NOT_A_NUMBER);
  }
  assert_int_equal(pv_parse_decimal("1e999", &v, err, sizeof err), PV_UI_ERR_OVERFLOW);
  assert_true(v == -2500.0);  // a refused number leaves the old value
  assert_int_equal(pv_parse_decimal("1", nullptr, err, sizeof err), PV_UI_ERR_INVALID_ARGUMENT);
}

void ranges_and_text(void **) {
  char err[200];
  double v = 0;
  assert_int_equal(pv_input_check(PV_INPUT_MASS_G, 4000, err, sizeof err), PV_UI_OK);
  assert_int_equal(pv_input_check(PV_INPUT_MASS_G, 1e308, err, sizeof err), PV_UI_ERR_OUT_OF_RANGE);
  assert_non_null(std::strstr(err, "mass 1e+308 g is outside 50 .. 100000 g"));
  assert_int_equal(pv_input_check(PV_INPUT_KIND_COUNT, 1, err, sizeof err), PV_UI_ERR_INVALID_ARGUMENT);
  assert_int_equal(pv_input_parse(PV_INPUT_MAX_DRY_KG_M3, "185", &v, err, sizeof err),
                   PV_UI_ERR_OUT_OF_RANGE);
  assert_non_null(std::strstr(err, "1000 .. 2800 kg/m3"));
  assert_int_equal(pv_input_parse(PV_INPUT_MAX_DRY_KG_M3, "1,85", &v, err, sizeof err),
                   PV_UI_ERR_DECIMAL_COMMA);
  assert_non_null(std::strstr(err, "max dry density: "));
  assert_int_equal(pv_input_parse(PV_INPUT_REQUIRED_PERCENT, "95", &v, err, sizeof err), PV_UI_OK);
  assert_true(v == 95.0);

  char out[8];
  assert_int_equal(pv_input_text("operator", "J. Oka", out, sizeof out, err, sizeof err), PV_UI_OK);
  assert_string_equal(out, "J. Oka");
  assert_int_equal(pv_input_text("operator", "J. Okafor", out, sizeof out, err, sizeof err),
                   PV_UI_ERR_TOO_LONG);
  assert_string_equal(err, "operator is longer than 7 characters");
  assert_int_equal(pv_input_text("operator", "a\tb", out, sizeof out, err, sizeof err),
                   PV_UI_ERR_CONTROL_CHAR);
  assert_non_null(std::strstr(err, "control character (byte 2)"));
  assert_string_equal(out, "J. Oka");  // a refused text leaves the old one
}

void settings_by_their_fault(void **) {
  pv_config_t cfg;
  pv_config_default(&cfg);
  const uint32_t knn_k = cfg.knn_k;
  char err[200];
  assert_int_equal(pv_config_field_set(&cfg, "layer_mm", "1.5", err, sizeof err), PV_UI_OK);
  assert_true(cfg.layer_mm == 1.5f);
  assert_int_equal(pv_config_field_set(&cfg, "method", "paper", err, sizeof err), PV_UI_OK);
  assert_int_equal(cfg.method, PV_METHOD_PAPER);
  assert_int_equal(pv_config_field_set(&cfg, "method", "best", err, sizeof err), PV_UI_ERR_UNKNOWN_METHOD);
  assert_int_equal(pv_config_field_set(&cfg, "layer_nm", "1", err, sizeof err), PV_UI_ERR_UNKNOWN_SETTING);
  assert_string_equal(err, "unknown setting 'layer_nm' (docs/method.md lists them)");
  assert_int_equal(pv_config_field_set(&cfg, "layer_mm", "9", err, sizeof err), PV_UI_ERR_OUT_OF_RANGE);
  assert_string_equal(err, "layer_mm = 9 is outside the allowed 0.1 .. 2");
  assert_int_equal(pv_config_field_set(&cfg, "knn_k", "8.5", err, sizeof err), PV_UI_ERR_NOT_WHOLE);
  assert_int_equal(pv_config_field_set(&cfg, "knn_k", "0x8", err, sizeof err), PV_UI_ERR_NOT_A_NUMBER);
  assert_non_null(std::strstr(err, "knn_k = '0x8' is not a decimal number"));
  assert_int_equal(pv_config_field_set(&cfg, "layer_mm", "0,5", err, sizeof err), PV_UI_ERR_DECIMAL_COMMA);
  assert_true(cfg.layer_mm == 1.5f);  // every refusal left the setting alone
  assert_int_equal(cfg.knn_k, knn_k);
}

void every_code_has_a_name_and_a_message(void **) {
  for (int code = PV_UI_ERR_INVALID_ARGUMENT; code <= PV_UI_ERR_UNKNOWN_METHOD; ++code) {
    const auto st = static_cast<pv_ui_status_t>(code);
    assert_true(code > PV_STATUS_BASE_UI && code < PV_STATUS_BASE_BOARD_CONFIG);
    assert_non_null(std::strstr(pv_ui_status_name(st), "PV_UI_ERR_"));
    assert_string_not_equal(pv_ui_status_name(st), "PV_UI_ERR_UNKNOWN");
    assert_string_not_equal(pv_ui_status_message(st), "unknown ui status");
  }
  assert_string_equal(pv_ui_status_name(static_cast<pv_ui_status_t>(849)), "PV_UI_ERR_UNKNOWN");
  assert_non_null(std::strstr(pv_ui_status_message(PV_UI_ERR_DECIMAL_COMMA), "1.5, not 1,5"));
}

// The board's screens and the advice print counts alike.
void counts_with_thousands_apart(void **) {
  char out[32];
  pv_advice_grouped(301989, out, sizeof out);
  assert_string_equal(out, "301 989");
  pv_advice_grouped(1000, out, sizeof out);
  assert_string_equal(out, "1 000");
  pv_advice_grouped(999, out, sizeof out);
  assert_string_equal(out, "999");
  pv_advice_grouped(0, out, sizeof out);
  assert_string_equal(out, "0");
  pv_advice_grouped(12345678, out, 6);  // cut to the room there is, still terminated
  assert_string_equal(out, "12 3");
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(decimals_by_their_fault),
      cmocka_unit_test(ranges_and_text),
      cmocka_unit_test(settings_by_their_fault),
      cmocka_unit_test(every_code_has_a_name_and_a_message),
      cmocka_unit_test(counts_with_thousands_apart),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
