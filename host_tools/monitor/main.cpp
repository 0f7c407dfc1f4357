// pitvol-monitor: talks to a pitvol board over its serial port.
//
//   pitvol-monitor PORT [options] [watch]        live status and results
//   pitvol-monitor PORT [options] fetch          the whole result log
//   pitvol-monitor PORT [options] hello | start | stop
//   pitvol-monitor PORT [options] set-mass GRAMS | set-moisture PERCENT
//
// Written in C++ on the board's own link layer and serial driver rather
// than in Python with pyserial: the monitor then frames, checks and decodes
// with the very code the board runs (one COBS, one CRC-32C, one set of
// nanopb structs from pitvol_link.proto), so the two ends cannot drift, and
// it needs nothing beyond the packages the firmware build installs.
#include <algorithm>
#include <cctype>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <sstream>
#include <set>
#include <string>
#include <vector>

#include <chrono>

#include <unistd.h>

#include "host_link.h"
#include "pitvol/json.h"
#include "pitvol/user_input.h"
#include "report.h"

namespace {

using pv::monitor::HostLink;
using Clock = std::chrono::steady_clock;

constexpr int kExitOk = 0, kExitRefused = 1, kExitUsage = 2, kExitNoAnswer = 3, kExitPort = 4;

const char *kUsage =
    "usage: pitvol-monitor PORT [options] [command]\n"
    "commands:\n"
    "  watch               live status, results and errors (default); lines on stdin\n"
    "                      are commands: start, stop, set-mass G, set-moisture P, hello, quit\n"
    "  fetch               every result in the board's log (CSV, or --json)\n"
    "  hello               the board's version, id and log range\n"
    "  start | stop        start or stop a scan\n"
    "  set-mass GRAMS      wet mass of the excavated soil, for the density\n"
    "  set-moisture PCT    water content in % of dry mass, for the dry density\n"
    "  set-test-id ID      the next result's test number (used up by it)\n"
    "  set-location TEXT   where the test is: station, offset, lift\n"
    "  set-operator NAME   who runs the test\n"
    "  set-max-dry-density KG_M3   Proctor maximum dry density (1000 .. 2800)\n"
    "  set-required-compaction PCT required relative compaction (50 .. 110): the verdict\n"
    "options:\n"
    "  --baud N            serial rate (default 115200)\n"
    "  --json              one JSON object per line\n"
    "  --from ID           fetch: start at result ID (default 1)\n"
    "  --count N           watch: stop after N results\n"
    "  --seconds S         watch: stop after S seconds\n"
    "  --retry-ms MS       command: wait this long for an answer before repeating (default 500)\n"
    "  --tries N           command: send at most N times (default 10)\n"
    "exit status: 0 ok, 1 refused by the board (or results missing from its log),\n"
    "             2 usage, 3 no answer, 4 port error\n";

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

struct Options {
  std::string port, command = "watch", arg;
  uint32_t baud = 115200;
  bool json = false;
  uint32_t from = 1;
  long count = -1;
  double seconds = -1;
  int retry_ms = 500, tries = 10;
};

// One line: what was wrong and where the commands are listed.
int usage(const std::string &msg) {
  std::fprintf(stderr, "pitvol-monitor: %s (pitvol-monitor --help lists the commands)\n", msg.c_str());
  return kExitUsage;
}

bool parse_number(const char *s, double *out) {
  char why[160];
  return pv_parse_decimal(s, out, why, sizeof why) == PV_UI_OK;
}

// Prints each message the board sends, once per result id.
struct Printer {
  bool json;
  std::set<uint32_t> printed;
  Clock::time_point last_status{};
  int last_state = -1;

  void operator()(const pv_link_rx_t &rx) {
    const pitvol_Message &m = rx.msg;
    switch (m.which_body) {
      case pitvol_Message_hello_tag:
        line(json ? pv::monitor::hello_json(m.body.hello) : pv::monitor::hello_text(m.body.hello));
        break;
      case pitvol_Message_status_tag: {
        // Human output: on a change of state or once a second.
        const auto now = Clock::now();
        if (json || m.body.status.state != last_state || now - last_status > std::chrono::seconds(1)) {
          line(json ? pv::monitor::status_json(m.body.status) : pv::monitor::status_text(m.body.status));
          last_status = now;
          last_state = m.body.status.state;
        }
        break;
      }
      case pitvol_Message_result_tag:
        if (printed.insert(m.body.result.id).second)
          line(json ? pv::monitor::result_json(m.body.result) : pv::monitor::result_text(m.body.result));
        break;
      case pitvol_Message_error_tag:
        line(json ? pv::monitor::error_json(m.body.error) : pv::monitor::error_text(m.body.error));
        break;
      default: break;
    }
  }
  static void line(const std::string &s) {
    std::printf("%s\n", s.c_str());
    std::fflush(stdout);
  }
};

int no_answer(HostLink::Reply r, const std::string &err) {
  std::fprintf(stderr, "pitvol-monitor: %s\n", err.c_str());
  return r == HostLink::Reply::PortError ? kExitPort : kExitNoAnswer;
}

int refused(const pv_link_rx_t &reply) {
  std::fprintf(stderr, "pitvol-monitor: the board refused: %s\n", pv::monitor::printable(reply.msg.body.nack.reason).c_str());
  return kExitRefused;
}

// Every result from opt.from on. Lost results are asked for again by id
// until the board's Ack says the range is complete.
int fetch(HostLink &link, const Options &opt) {
  std::map<uint32_t, pitvol_Result> got;
  const auto keep = [&](const pv_link_rx_t &rx) {
    if (rx.msg.which_body == pitvol_Message_result_tag && rx.msg.body.result.id >= opt.from)
      got.emplace(rx.msg.body.result.id, rx.msg.body.result);
  };
  uint32_t ask_from = opt.from, ask_count = 0, first = 0, last = 0;
  // Ids the board said it has not got (asked for by id, none sent): a
  // damaged record. Reported, not asked for forever.
  std::set<uint32_t> unavailable;
  std::string err;
  for (int round = 0;; ++round) {
    if (round == 1000) {
      std::fprintf(stderr, "pitvol-monitor: the log could not be read completely; the line is too noisy\n");
      return kExitNoAnswer;
    }
    pitvol_Message cmd = pitvol_Message_init_zero;
    cmd.which_body = pitvol_Message_get_results_tag;
    cmd.body.get_results.from_id = ask_from;
    cmd.body.get_results.to_id = ask_count ? ask_from + ask_count - 1 : 0;
    pv_link_rx_t reply;
    const HostLink::Reply r = link.command(cmd, &reply, keep, opt.retry_ms, opt.tries, &err);
    if (r == HostLink::Reply::Nack) return refused(reply);
    if (r != HostLink::Reply::Ack) return no_answer(r, err);
    if (round == 0 || reply.msg.body.ack.last_id > last) last = reply.msg.body.ack.last_id;
    first = reply.msg.body.ack.first_id;
    if (ask_count > 0 && reply.msg.body.ack.sent_count == 0)
      for (uint32_t id = ask_from; id < ask_from + ask_count; ++id) unavailable.insert(id);
    // The first id still wanted, and the run of missing ids from there.
    const uint32_t lo = std::max(opt.from, first);
    uint32_t missing = 0;
    if (last != 0)
      for (uint32_t id = lo; id <= last; ++id)
        if (!got.count(id) && !unavailable.count(id)) { missing = id; break; }
    if (missing == 0) break;
    uint32_t run = 0;
    while (missing + run <= last && !got.count(missing + run) && !unavailable.count(missing + run) &&
           run < 64)
      ++run;
    ask_from = missing;
    ask_count = run;
  }
  if (!opt.json) std::printf("%s\n", pv::monitor::result_csv_header().c_str());
  for (const auto &[id, res] : got) {
    if (id > last || id < first) continue;
    std::printf("%s\n", (opt.json ? pv::monitor::result_json(res) : pv::monitor::result_csv_row(res)).c_str());
  }
  std::fprintf(stderr, "pitvol-monitor: %zu results; %u corrupt frames on the line\n",
               size_t(std::count_if(got.begin(), got.end(),
                                    [&](const auto &kv) { return kv.first >= first && kv.first <= last; })),
               link.stats().frames_corrupt);
  if (!unavailable.empty()) {
    std::fprintf(stderr, "pitvol-monitor: %zu results (ids %u .. %u) are not in the board's log: "
                 "its storage is damaged there; the other results are complete\n",
                 unavailable.size(), *unavailable.begin(), *unavailable.rbegin());
    return kExitRefused;
  }
  return kExitOk;
}

// A command by name ("start", "set-mass", ...) with its argument.
bool make_command(const std::string &name, const std::string &arg, pitvol_Message *cmd,
                  std::string *err) {
  *cmd = pitvol_Message_init_zero;
  double v = 0;
  if (name == "hello") {
    cmd->which_body = pitvol_Message_get_hello_tag;
  } else if (name == "start") {
    cmd->which_body = pitvol_Message_start_scan_tag;
  } else if (name == "stop") {
    cmd->which_body = pitvol_Message_stop_scan_tag;
  } else if (name == "set-mass" || name == "set-moisture") {
    // The syntax here (0x10, 1,5 or inf never reach the board as another
    // number); the range is the board's to check: its refusal names it.
    char why[160];
    if (arg.empty() || pv_parse_decimal(arg.c_str(), &v, why, sizeof why) != PV_UI_OK) {
      *err = name + " needs a number (" + (name == "set-mass" ? "grams" : "percent of dry mass") + ")" +
             (arg.empty() ? "" : std::string(": ") + why);
      return false;
    }
    if (name == "set-mass") {
      cmd->which_body = pitvol_Message_set_mass_tag;
      cmd->body.set_mass.mass_g = v;
    } else {
      cmd->which_body = pitvol_Message_set_moisture_tag;
      cmd->body.set_moisture.moisture_percent = v;
    }
  } else if (name == "set-test-id" || name == "set-location" || name == "set-operator") {
    // Text for the record: the board checks it (printable, its length).
    cmd->which_body = pitvol_Message_set_record_tag;
    pitvol_SetRecord &r = cmd->body.set_record;
    char *dst = name == "set-test-id" ? r.test_id : name == "set-location" ? r.location : r.operator_name;
    const size_t cap = name == "set-test-id" ? sizeof r.test_id
                       : name == "set-location" ? sizeof r.location : sizeof r.operator_name;
    if (arg.size() + 1 > cap) {
      *err = name + ": at most " + std::to_string(cap - 1) + " characters";
      return false;
    }
    std::snprintf(dst, cap, "%s", arg.c_str());
    r.fields = name == "set-test-id" ? pitvol_RecordField_RECORD_TEST_ID
               : name == "set-location" ? pitvol_RecordField_RECORD_LOCATION : pitvol_RecordField_RECORD_OPERATOR;
  } else if (name == "set-max-dry-density" || name == "set-required-compaction") {
    char why[160];
    if (arg.empty() || pv_parse_decimal(arg.c_str(), &v, why, sizeof why) != PV_UI_OK) {
      *err = name + " needs a number" + (arg.empty() ? "" : std::string(": ") + why);
      return false;
    }
    cmd->which_body = pitvol_Message_set_record_tag;
    pitvol_SetRecord &r = cmd->body.set_record;
    if (name == "set-max-dry-density") {
      r.fields = pitvol_RecordField_RECORD_MAX_DRY_DENSITY;
      r.max_dry_density_kg_m3 = v;
    } else {
      r.fields = pitvol_RecordField_RECORD_REQUIRED_COMPACTION;
      r.required_compaction_percent = v;
    }
  } else {
    *err = "unknown command '" + name + "'";
    return false;
  }
  return true;
}

// Live: everything the board says. A result id that skips ahead (or a
// Status naming a newer result) means results were lost on the line; they
// are asked for again by id. Lines on stdin are commands ("start", "stop",
// "set-mass 3000", "set-moisture 12.5", "hello"), sent one at a time and
// repeated until the board answers; the answer is printed.
int watch(HostLink &link, const Options &opt) {
  Printer print{opt.json, {}, {}, -1};
  uint32_t highest = 0;
  bool have_highest = false;
  std::set<uint32_t> missing;
  long results = 0;
  struct Pending {
    pitvol_Message msg;
    std::string text;
    uint32_t seq = 0;
    int sent = 0;
    Clock::time_point at{};
  };
  std::deque<Pending> commands;
  const auto answer = [&](const pitvol_Message &m) {
    if (commands.empty() || commands.front().sent == 0) return;
    const uint32_t seq = m.which_body == pitvol_Message_ack_tag ? m.body.ack.command_seq : m.body.nack.command_seq;
    if (seq != commands.front().seq) return;
    const std::string &c = commands.front().text;
    pv::tools::Json o = {{"type", m.which_body == pitvol_Message_ack_tag ? "ack" : "nack"}, {"command", c}};
    if (m.which_body == pitvol_Message_ack_tag) {
      Printer::line(opt.json ? pv::tools::json_line(o) : "ok       " + pv::monitor::printable(c));
    } else {
      o["reason"] = std::string(m.body.nack.reason);
      Printer::line(opt.json ? pv::tools::json_line(o)
                             : "refused  " + pv::monitor::printable(c) + ": " +
                                   pv::monitor::printable(m.body.nack.reason));
    }
    commands.pop_front();
  };
  const auto handle = [&](const pv_link_rx_t &rx) {
    const pitvol_Message &m = rx.msg;
    if (m.which_body == pitvol_Message_result_tag) {
      const uint32_t id = m.body.result.id;
      if (!print.printed.count(id)) results++;
      missing.erase(id);
      if (!have_highest) {
        have_highest = true;
        highest = id;
      }
      for (uint32_t i = highest + 1; i < id && missing.size() < 4096; ++i) missing.insert(i);
      if (id > highest) highest = id;
    } else if (m.which_body == pitvol_Message_status_tag && have_highest &&
               m.body.status.last_result_id > highest) {
      for (uint32_t i = highest + 1; i <= m.body.status.last_result_id && missing.size() < 4096; ++i)
        missing.insert(i);
      highest = m.body.status.last_result_id;
    } else if (m.which_body == pitvol_Message_hello_tag && !have_highest) {
      have_highest = true;
      highest = m.body.hello.last_result_id;
    } else if (m.which_body == pitvol_Message_ack_tag || m.which_body == pitvol_Message_nack_tag) {
      answer(m);
    }
    print(rx);
  };
  // Hello first: where the log stands now.
  pitvol_Message hello = pitvol_Message_init_zero;
  hello.which_body = pitvol_Message_get_hello_tag;
  pv_link_rx_t reply;
  std::string err;
  const HostLink::Reply r = link.command(hello, &reply, handle, opt.retry_ms, opt.tries, &err);
  if (r != HostLink::Reply::Ack) return r == HostLink::Reply::Nack ? refused(reply) : no_answer(r, err);
  const auto start = Clock::now();
  auto last_ask = Clock::now() - std::chrono::seconds(10);
  int in_fd = STDIN_FILENO;
  std::string in_buf;
  while (!g_stop) {
    if (opt.count >= 0 && results >= opt.count && commands.empty()) break;
    if (opt.seconds >= 0 && std::chrono::duration<double>(Clock::now() - start).count() > opt.seconds) break;
    const auto now = Clock::now();
    if (!missing.empty() && now - last_ask > std::chrono::milliseconds(opt.retry_ms)) {
      pitvol_Message ask = pitvol_Message_init_zero;
      ask.which_body = pitvol_Message_get_results_tag;
      ask.body.get_results.from_id = *missing.begin();
      ask.body.get_results.to_id = std::min<uint32_t>(*missing.begin() + 63, *missing.rbegin());
      if (!link.post(ask, nullptr, &err)) return no_answer(HostLink::Reply::PortError, err);
      last_ask = now;
    }
    if (!commands.empty()) {
      Pending &c = commands.front();
      if (c.sent == 0 || now - c.at > std::chrono::milliseconds(opt.retry_ms)) {
        if (c.sent == opt.tries) {
          std::fprintf(stderr, "pitvol-monitor: %s: the board did not answer\n", c.text.c_str());
          commands.pop_front();
        } else if (c.sent == 0 ? link.post(c.msg, &c.seq, &err) : link.post_again(c.msg, c.seq, &err)) {
          c.sent++;
          c.at = now;
        }
      }
    }
    bool stdin_ready = false;
    if (!link.pump(100, handle, &err, in_fd, &stdin_ready)) {
      std::fprintf(stderr, "pitvol-monitor: %s\n", err.c_str());
      return kExitPort;
    }
    if (!stdin_ready) continue;
    char buf[256];
    const ssize_t n = read(in_fd, buf, sizeof buf);
    if (n <= 0) {
      in_fd = -1;  // end of input: keep watching
      continue;
    }
    in_buf.append(buf, size_t(n));
    size_t eol;
    while ((eol = in_buf.find('\n')) != std::string::npos) {
      std::string line = in_buf.substr(0, eol);
      in_buf.erase(0, eol + 1);
      std::istringstream words(line);
      std::string name, arg;
      words >> name;
      std::getline(words >> std::ws, arg);  // the rest: a location has spaces
      if (name.empty()) continue;
      if (name == "quit") {
        g_stop = 1;
        break;
      }
      Pending p;
      p.text = line;
      if (!make_command(name, arg, &p.msg, &err)) {
        std::fprintf(stderr, "pitvol-monitor: %s\n", err.c_str());
        continue;
      }
      commands.push_back(p);
    }
  }
  return kExitOk;
}

int simple_command(HostLink &link, const Options &opt) {
  pitvol_Message cmd;
  std::string why;
  if (!make_command(opt.command, opt.arg, &cmd, &why)) return usage(why);
  // Only the answer matters here (and the Hello it asked for).
  const auto print = [&](const pv_link_rx_t &rx) {
    if (rx.msg.which_body == pitvol_Message_hello_tag)
      Printer::line(opt.json ? pv::monitor::hello_json(rx.msg.body.hello) : pv::monitor::hello_text(rx.msg.body.hello));
  };
  pv_link_rx_t reply;
  std::string err;
  const HostLink::Reply r = link.command(cmd, &reply, print, opt.retry_ms, opt.tries, &err);
  if (r == HostLink::Reply::Nack) return refused(reply);
  if (r != HostLink::Reply::Ack) return no_answer(r, err);
  if (opt.command != "hello") Printer::line(opt.json ? "{\"type\":\"ack\"}" : "ok");
  return kExitOk;
}

}  // namespace

int main(int argc, char **argv) {
  Options opt;
  std::vector<std::string> pos;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char *name) -> const char * {
      if (i + 1 >= argc) return nullptr;
      (void)name;
      return argv[++i];
    };
    double v = 0;
    if (a == "-h" || a == "--help") {
      std::printf("%s", kUsage);
      return kExitOk;
    } else if (a == "--json") {
      opt.json = true;
    } else if (a == "--baud" || a == "--from" || a == "--count" || a == "--seconds" ||
               a == "--retry-ms" || a == "--tries") {
      const char *s = value(a.c_str());
      if (!s || !parse_number(s, &v) || v < 0) return usage(a + " needs a number >= 0");
      if (a == "--baud") opt.baud = uint32_t(v);
      else if (a == "--from") opt.from = uint32_t(v);
      else if (a == "--count") opt.count = long(v);
      else if (a == "--seconds") opt.seconds = v;
      else if (a == "--retry-ms") opt.retry_ms = int(v);
      else opt.tries = int(v);
    } else if (a.size() > 1 && a[0] == '-' && !(a.size() > 1 && (std::isdigit(a[1]) || a[1] == '.'))) {
      return usage("unknown option " + a);
    } else {
      pos.push_back(a);
    }
  }
  if (pos.empty()) return usage("give the serial port, e.g. /dev/ttyUSB0");
  opt.port = pos[0];
  if (pos.size() > 1) opt.command = pos[1];
  // The record's words may come unquoted: set-location STA 1+250, lift 3.
  const bool text = opt.command == "set-test-id" || opt.command == "set-location" || opt.command == "set-operator";
  if (pos.size() > 3 && !text) return usage("too many arguments");
  for (size_t i = 2; i < pos.size(); ++i) opt.arg += (i > 2 ? " " : "") + pos[i];
  if (!pv_serial_baud_supported(opt.baud)) return usage("unsupported baud rate");
  if (opt.tries < 1) opt.tries = 1;

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  HostLink link;
  std::string err;
  if (!link.open(opt.port, opt.baud, &err)) {
    std::fprintf(stderr, "pitvol-monitor: %s\n", err.c_str());
    return kExitPort;
  }
  if (opt.command == "watch") return watch(link, opt);
  if (opt.command == "fetch") return fetch(link, opt);
  return simple_command(link, opt);
}
