// The link server (lib/link/link_server.c) and the result's message
// (lib/link/link_result.c) in-process: a host pv_link_t talks to the server
// over byte vectors, the server reads a real result log in a temporary
// directory, and a scripted application stands behind it.
#include <dirent.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "pitvol/link.h"
#include "pitvol/link_result.h"
#include "pitvol/link_server.h"
#include "pitvol/result_log.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using Bytes = std::vector<uint8_t>;

// A board clock that was never set reads 1970: its results carry time 0
// ("clock not set", which pitvol-monitor prints as clock-not-set), never a
// false date; from 2024-01-01T00:00:00Z (1704067200) on a reading is a date.
void result_time_is_zero_for_an_unset_clock(void **) {
  assert_int_equal(pv_link_result_time(0), 0);
  assert_int_equal(pv_link_result_time(86400 * 30), 0);           // 1970-01-31
  assert_int_equal(pv_link_result_time(1704067199), 0);           // 2023-12-31T23:59:59Z
  assert_int_equal(pv_link_result_time(-5), 0);
  assert_int_equal(pv_link_result_time(1704067200), 1704067200);  // 2024-01-01T00:00:00Z
  assert_int_equal(pv_link_result_time(1796083200), 1796083200);  // 2026-12-01
}

pv_result_t core_result(pv_status_t status) {
  pv_result_t r{};
  r.status = status;
  // What a refused scan may leave in the result: the message must not carry it.
  r.volume_cm3 = 1234.5;
  r.interval_cm3 = 12.0;
  r.depth_mm = 150.0;
  r.failed_check = 3;
  r.check_value = 0.25;
  r.check_limit = 0.5;
  r.gap_from_mm = 40.0;
  r.gap_to_mm = 80.0;
  r.points_in = 1000;
  r.points_used = 900;
  return r;
}

pitvol_Result message_of(const pv_result_t &r, const pv_density_t *d = nullptr,
                         const pv_link_record_t *rec = nullptr) {
  const pv_link_result_source_t src = {r.status, &r, "surface", 1790000000, d, 3000.0, 12.5, rec};
  pitvol_Result out;
  pv_link_result_message(&out, &src);
  return out;
}

// A result without a volume carries none (nor interval, depth) and says
// why; a measured one carries its volume and no refusal.
void a_failed_result_carries_no_volume(void **) {
  const pitvol_Result ok = message_of(core_result(PV_OK));
  assert_true(ok.volume_cm3 == 1234.5 && ok.interval_cm3 == 12.0 && ok.depth_mm == 150.0);
  assert_int_equal(ok.failed_check, 0);
  assert_true(ok.gap_to_mm == 0.0);
  assert_int_equal(ok.time_unix_s, 1790000000);
  assert_string_equal(ok.method, "surface");

  const pitvol_Result pit = message_of(core_result(PV_ERR_NOT_A_PIT));
  assert_int_equal(pit.status, PV_ERR_NOT_A_PIT);
  assert_true(pit.volume_cm3 == 0.0 && pit.interval_cm3 == 0.0 && pit.depth_mm == 0.0);
  assert_int_equal(pit.failed_check, 3);
  assert_true(pit.check_value == 0.25 && pit.check_limit == 0.5);
  assert_true(pit.gap_from_mm == 0.0 && pit.gap_to_mm == 0.0);
  assert_int_equal(pit.points_in, 1000);

  const pitvol_Result gap = message_of(core_result(PV_ERR_WALL_GAP));
  assert_true(gap.volume_cm3 == 0.0 && gap.depth_mm == 0.0);
  assert_true(gap.gap_from_mm == 40.0 && gap.gap_to_mm == 80.0);
  assert_int_equal(gap.failed_check, 0);

  const pitvol_Result rim = message_of(core_result(PV_ERR_NO_RIM));
  assert_true(rim.volume_cm3 == 0.0 && rim.failed_check == 0 && rim.gap_to_mm == 0.0);
}

// Density and record: copied as the board shows them; the record's maximum
// dry density is the density's reference, its verdict from the density.
void density_and_record_in_the_message(void **) {
  // monitor_e2e.sh's result 21: 3000 g, 12.5 %, 1525 +/- 30 cm3, 1850 kg/m3.
  const pv_density_input_t in = {1525, 30, 1, 3000, 1, 12.5, 1850};
  pv_density_t d{};
  assert_int_equal(pv_density_compute(&in, &d), PV_DENSITY_OK);
  pv_link_record_t rec{};
  std::snprintf(rec.test_id, sizeof rec.test_id, "FDT-0023");
  rec.max_dry_density_kg_m3 = 1850;
  rec.required_compaction_percent = 95;
  pv_result_t r = core_result(PV_OK);
  r.volume_cm3 = 1525;
  r.interval_cm3 = 30;
  const pitvol_Result m = message_of(r, &d, &rec);
  assert_true(m.has_density);
  assert_int_equal(m.density.flags, d.flags);
  assert_true(m.density.mass_g == 3000 && m.density.moisture_percent == 12.5);
  assert_true(m.density.reference_max_dry_kg_m3 == 1850);
  assert_true(m.has_record);
  assert_string_equal(m.record.test_id, "FDT-0023");
  assert_int_equal(m.record.verdict, pitvol_Verdict_VERDICT_UNDECIDED);
  // Compaction 94.52 % of 95 %: 1525 x (1 - 94.52 / 95) = 7.69 cm3 would decide.
  assert_true(m.record.decides_within_cm3 > 7.6 && m.record.decides_within_cm3 < 7.8);
  // No density: none in the message.
  assert_false(message_of(r, nullptr, &rec).has_density);
}

void record_apply_is_all_or_nothing(void **) {
  pv_link_record_t rec{};
  std::snprintf(rec.location, sizeof rec.location, "STA 1");
  pitvol_SetRecord s = pitvol_SetRecord_init_zero;
  s.fields = pitvol_RecordField_RECORD_TEST_ID | pitvol_RecordField_RECORD_REQUIRED_COMPACTION;
  std::snprintf(s.test_id, sizeof s.test_id, "FDT-1");
  s.required_compaction_percent = 400;  // outside 50 .. 110
  char why[120] = "";
  assert_int_equal(pv_link_record_apply(&rec, &s, why, sizeof why), PV_LINK_RECORD_OUT_OF_RANGE);
  assert_non_null(std::strstr(why, "outside"));
  assert_string_equal(rec.test_id, "");
  // A control character in a text field: refused as text, nothing applied.
  s.required_compaction_percent = 95;
  std::snprintf(s.test_id, sizeof s.test_id, "FDT\n1");
  assert_int_equal(pv_link_record_apply(&rec, &s, why, sizeof why), PV_LINK_RECORD_TEXT);
  assert_string_equal(rec.test_id, "");
  assert_true(rec.required_compaction_percent == 0);
  assert_string_equal(pv_link_status_name(PV_LINK_RECORD_TEXT), "PV_LINK_RECORD_TEXT");
  assert_string_equal(pv_link_status_name(PV_LINK_RECORD_OUT_OF_RANGE),
                      "PV_LINK_RECORD_OUT_OF_RANGE");
  std::snprintf(s.test_id, sizeof s.test_id, "FDT-1");
  assert_int_equal(pv_link_record_apply(&rec, &s, why, sizeof why), PV_LINK_OK);
  assert_string_equal(rec.test_id, "FDT-1");
  assert_string_equal(rec.location, "STA 1");
  assert_true(rec.required_compaction_percent == 95);
}

// The scripted application.
struct App {
  int starts = 0;
  double mass = 0;
  pv_link_record_t record{};
};

void app_status(void *, pitvol_Status *s) { s->state = pitvol_DeviceState_STATE_IDLE; }
pitvol_NackCode app_start(void *ctx, char *, size_t) {
  static_cast<App *>(ctx)->starts++;
  return pitvol_NackCode_NACK_NONE;
}
pitvol_NackCode app_stop(void *, char *why, size_t cap) {
  std::snprintf(why, cap, "no scan is running; start one first");
  return pitvol_NackCode_NACK_WRONG_STATE;
}
void app_density(void *ctx, pv_input_kind_t kind, double v) {
  if (kind == PV_INPUT_MASS_G) static_cast<App *>(ctx)->mass = v;
}
void app_get_record(void *ctx, pv_link_record_t *out) { *out = static_cast<App *>(ctx)->record; }
void app_set_record(void *ctx, const pv_link_record_t *r) { static_cast<App *>(ctx)->record = *r; }
const pv_link_app_t kApp = {app_status, app_start, app_stop, app_density, app_get_record,
                            app_set_record, nullptr};

// A port that takes at most `per_call` bytes a write, and nothing every
// third call: the server must stream the log as the link drains.
struct Port {
  Bytes bytes;
  size_t per_call = 97;
  unsigned calls = 0;
};
long port_write(void *ctx, const uint8_t *data, size_t len) {
  Port *p = static_cast<Port *>(ctx);
  if (++p->calls % 3 == 0) return 0;
  const size_t n = len < p->per_call ? len : p->per_call;
  p->bytes.insert(p->bytes.end(), data, data + n);
  return long(n);
}

struct Rig {
  std::string dir;
  pv_log_t log{};
  App app;
  pv_link_server_t srv{};
  pv_link_t host{};
  Port port;
  std::vector<pitvol_Message> got;  // everything the host received but Status

  explicit Rig(bool with_log) {
    const char *base = std::getenv("TMPDIR");
    std::string templ = std::string(base && *base ? base : "/tmp") + "/pv-server-XXXXXX";
    std::vector<char> buf(templ.begin(), templ.end());
    buf.push_back(0);
    assert_non_null(mkdtemp(buf.data()));
    dir = buf.data();
    pv_log_config_t cfg;
    pv_log_config_default(&cfg);
    assert_int_equal(pv_log_open(&log, dir.c_str(), &cfg), PV_LOG_OK);
    const pv_link_server_config_t sc = {&kApp, &app, with_log ? &log : nullptr, "PV-UNIT-1",
                                        pitvol_Capability_CAP_DENSITY, 5000};
    pv_link_server_init(&srv, &sc);
    pv_link_init(&host, 77);
  }
  ~Rig() {
    pv_log_close(&log);
    if (DIR *d = opendir(dir.c_str())) {
      while (dirent *e = readdir(d))
        if (e->d_name[0] != '.') unlink((dir + "/" + e->d_name).c_str());
      closedir(d);
    }
    rmdir(dir.c_str());
  }

  // The host sends msg (again under seq when seq != 0); returns its seq.
  uint32_t command(const pitvol_Message &msg, uint32_t again = 0) {
    uint32_t seq = again;
    if (again) {
      assert_int_equal(pv_link_send_again(&host, &msg, again), PV_LINK_OK);
    } else {
      assert_int_equal(pv_link_send(&host, &msg, PV_LINK_RELIABLE, &seq), PV_LINK_OK);
    }
    Port wire;
    wire.per_call = SIZE_MAX;
    wire.calls = 1;  // the host's writes all go through
    while (pv_link_tx_pending(&host)) {
      assert_int_equal(pv_link_tx_flush(&host, port_write, &wire), PV_LINK_OK);
      wire.calls = 1;
    }
    pv_link_server_feed(&srv, wire.bytes.data(), wire.bytes.size());
    return seq;
  }

  // Runs the server until it has nothing left; the host decodes it all.
  void drain() {
    for (int round = 0; round < 10000 && pv_link_server_busy(&srv); ++round)
      assert_int_equal(pv_link_server_service(&srv, port_write, &port), PV_LINK_OK);
    assert_false(pv_link_server_busy(&srv));
    for (size_t at = 0; at < port.bytes.size();) {
      pv_link_rx_t rx;
      int ok = 0;
      at += pv_link_feed(&host, port.bytes.data() + at, port.bytes.size() - at, &rx, &ok);
      if (ok && rx.msg.which_body != pitvol_Message_status_tag) got.push_back(rx.msg);
    }
    port.bytes.clear();
    assert_int_equal(host.stats.frames_corrupt, 0);
    assert_int_equal(host.stats.frames_missed, 0);
  }

  void log_result(uint32_t i) {
    pv_result_t r = core_result(PV_OK);
    r.volume_cm3 = 1500 + i;
    pitvol_Result m = message_of(r);
    assert_int_equal(pv_link_server_log_result(&srv, &m), PV_LOG_OK);
    assert_int_equal(m.id, pv_log_last_seq(&log));
  }
};

pitvol_Message body(pb_size_t tag) {
  pitvol_Message m = pitvol_Message_init_zero;
  m.which_body = tag;
  return m;
}

// GetResults over a log longer than the link's queue, through a port that
// takes a few bytes at a time: every record once, in order, a record that
// does not decode skipped and counted out of sent_count, then the Ack.
void get_results_streams_the_log(void **) {
  Rig rig(true);
  for (uint32_t i = 1; i <= 40; ++i) {
    if (i == 17) {
      const uint8_t junk[11] = {0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff};
      uint32_t seq = 0;
      assert_int_equal(pv_log_append(&rig.log, junk, sizeof junk, &seq), PV_LOG_OK);
      continue;
    }
    rig.log_result(i);
  }
  pitvol_Message get = body(pitvol_Message_get_results_tag);
  get.body.get_results.from_id = 3;
  get.body.get_results.to_id = 35;
  const uint32_t seq = rig.command(get);
  rig.drain();
  std::vector<uint32_t> ids;
  for (size_t i = 0; i + 1 < rig.got.size(); ++i) {
    assert_int_equal(rig.got[i].which_body, pitvol_Message_result_tag);
    ids.push_back(rig.got[i].body.result.id);
    assert_true(rig.got[i].body.result.volume_cm3 == 1500.0 + rig.got[i].body.result.id);
  }
  std::vector<uint32_t> want;
  for (uint32_t i = 3; i <= 35; ++i)
    if (i != 17) want.push_back(i);
  assert_true(ids == want);
  const pitvol_Message &last = rig.got.back();
  assert_int_equal(last.which_body, pitvol_Message_ack_tag);
  assert_int_equal(last.body.ack.command_seq, seq);
  assert_int_equal(last.body.ack.sent_count, 32);
  assert_int_equal(last.body.ack.first_id, 1);
  assert_int_equal(last.body.ack.last_id, 40);
}

// Commands: Hello then its Ack; the application's refusal with its reason;
// a mass out of range refused before the application sees it; a repeated
// command answered again without reaching the application.
void commands_reach_the_application(void **) {
  Rig rig(true);
  rig.log_result(1);
  const uint32_t hello = rig.command(body(pitvol_Message_get_hello_tag));
  rig.drain();
  assert_int_equal(rig.got.size(), 2);
  assert_int_equal(rig.got[0].which_body, pitvol_Message_hello_tag);
  assert_string_equal(rig.got[0].body.hello.device_id, "PV-UNIT-1");
  assert_int_equal(rig.got[0].body.hello.capabilities,
                   pitvol_Capability_CAP_DENSITY | pitvol_Capability_CAP_RESULT_LOG);
  assert_int_equal(rig.got[0].body.hello.last_result_id, 1);
  assert_int_equal(rig.got[1].body.ack.command_seq, hello);
  rig.got.clear();

  rig.command(body(pitvol_Message_stop_scan_tag));
  pitvol_Message mass = body(pitvol_Message_set_mass_tag);
  mass.body.set_mass.mass_g = -5;
  rig.command(mass);
  mass.body.set_mass.mass_g = 2500;
  rig.command(mass);
  const uint32_t start = rig.command(body(pitvol_Message_start_scan_tag));
  rig.command(body(pitvol_Message_start_scan_tag), start);  // the host repeats it
  rig.drain();
  assert_int_equal(rig.got.size(), 5);
  assert_int_equal(rig.got[0].body.nack.code, pitvol_NackCode_NACK_WRONG_STATE);
  assert_string_equal(rig.got[0].body.nack.reason, "no scan is running; start one first");
  assert_int_equal(rig.got[1].body.nack.code, pitvol_NackCode_NACK_OUT_OF_RANGE);
  assert_int_equal(rig.got[2].which_body, pitvol_Message_ack_tag);
  assert_true(rig.app.mass == 2500);
  assert_int_equal(rig.got[3].body.ack.command_seq, start);
  assert_int_equal(rig.got[4].body.ack.command_seq, start);
  assert_int_equal(rig.app.starts, 1);

  pitvol_Message rec = body(pitvol_Message_set_record_tag);
  rec.body.set_record.fields = pitvol_RecordField_RECORD_OPERATOR;
  std::snprintf(rec.body.set_record.operator_name, sizeof rec.body.set_record.operator_name, "J. Okafor");
  rig.command(rec);
  rig.drain();
  assert_string_equal(rig.app.record.operator_name, "J. Okafor");
}

// A result without a volume: logged, then Result, the Error naming its
// status, and a Status with its id. Without a log GetResults is refused
// and a result goes out with id 0.
void a_result_goes_out_after_the_log(void **) {
  Rig rig(true);
  pitvol_Result m = message_of(core_result(PV_ERR_NO_RIM));
  const pv_log_status_t st = pv_link_server_log_result(&rig.srv, &m);
  assert_int_equal(st, PV_LOG_OK);
  assert_int_equal(m.id, 1);
  pv_link_server_send_result(&rig.srv, &m, st);
  rig.drain();
  assert_int_equal(rig.got.size(), 2);
  assert_int_equal(rig.got[0].which_body, pitvol_Message_result_tag);
  assert_int_equal(rig.got[0].body.result.id, 1);
  assert_true(rig.got[0].body.result.volume_cm3 == 0.0);
  assert_int_equal(rig.got[1].which_body, pitvol_Message_error_tag);
  assert_int_equal(rig.got[1].body.error.code, PV_ERR_NO_RIM);
  assert_string_equal(rig.got[1].body.error.name, "PV_ERR_NO_RIM");

  Rig bare(false);
  pitvol_Result n = message_of(core_result(PV_OK));
  assert_int_equal(pv_link_server_log_result(&bare.srv, &n), PV_LOG_OK);
  assert_int_equal(n.id, 0);
  bare.command(body(pitvol_Message_get_results_tag));
  bare.drain();
  assert_int_equal(bare.got.size(), 1);
  assert_int_equal(bare.got[0].body.nack.code, pitvol_NackCode_NACK_STORAGE);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(result_time_is_zero_for_an_unset_clock),
      cmocka_unit_test(a_failed_result_carries_no_volume),
      cmocka_unit_test(density_and_record_in_the_message),
      cmocka_unit_test(record_apply_is_all_or_nothing),
      cmocka_unit_test(get_results_streams_the_log),
      cmocka_unit_test(commands_reach_the_application),
      cmocka_unit_test(a_result_goes_out_after_the_log),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
