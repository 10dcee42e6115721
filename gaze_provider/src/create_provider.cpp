// create_gaze_provider(): the source-string front door used by the layer and gaze-diag.
#include <charconv>

#include "gaze_provider/backends.h"

namespace foveart::gaze {

namespace {
bool parse_hex16(std::string_view s, std::uint16_t& out) {
  if (s.starts_with("0x") || s.starts_with("0X")) s.remove_prefix(2);
  if (s.empty() || s.size() > 4) return false;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out, 16);
  return ec == std::errc{} && p == s.data() + s.size();
}
}  // namespace

CreateResult create_gaze_provider(std::string_view source) { return create_gaze_provider(source, ProviderOptions{}); }

CreateResult create_gaze_provider(std::string_view source, const ProviderOptions& options) {
  CreateResult r;
  const std::size_t colon = source.find(':');
  const std::string_view kind = source.substr(0, colon);
  const std::string_view arg = colon == std::string_view::npos ? std::string_view{} : source.substr(colon + 1);
  const bool has_arg = colon != std::string_view::npos;

  if (kind == "sim") {
    SimConfig sim = options.sim;
    if (has_arg) {
      auto [p, ec] = std::from_chars(arg.data(), arg.data() + arg.size(), sim.seed);
      if (ec != std::errc{} || p != arg.data() + arg.size()) {
        r.error = "source '" + std::string(source) + "': sim:SEED needs an unsigned integer seed";
        return r;
      }
    }
    r.provider = create_sim_provider(sim, options, &r.error);
  } else if (kind == "replay") {
    if (arg.empty()) {
      r.error = "source '" + std::string(source) + "': expected replay:FILE";
      return r;
    }
    ReplayConfig replay = options.replay;
    replay.path = std::string(arg);
    r.provider = create_replay_provider(replay, options, &r.error);
  } else if (kind == "fove") {
    FoveConfig fove = options.fove;
    if (has_arg && !arg.empty()) fove.library_path = std::string(arg);
    r.provider = create_fove_provider(fove, options, &r.error);
  } else if (kind == "hid") {
    HidConfig hid = options.hid;
    if (has_arg) {
      const std::size_t c2 = arg.find(':');
      std::uint16_t vid = 0, pid = 0;
      if (arg.starts_with("/")) {
        hid.path = std::string(arg);
      } else if (c2 == std::string_view::npos || !parse_hex16(arg.substr(0, c2), vid) ||
                 !parse_hex16(arg.substr(c2 + 1), pid)) {
        r.error = "source '" + std::string(source) + "': expected hid:VID:PID with hexadecimal ids (e.g. hid:2a5e:0001)";
        return r;
      } else {
        hid.vendor_id = vid;
        hid.product_id = pid;
      }
    }
    r.provider = create_hid_provider(hid, options, &r.error);
  } else {
    r.error = "unknown gaze source '" + std::string(source) +
              "' (expected sim, sim:SEED, replay:FILE, fove, fove:LIBRARY, hid, hid:VID:PID, hid:/dev/hidrawN)";
  }
  if (!r.provider && r.error.empty()) r.error = "cannot create gaze source '" + std::string(source) + "'";
  return r;
}

}  // namespace foveart::gaze
