#include "station/app/run_summary.h"

#include <cinttypes>
#include <nlohmann/json.hpp>

#include "station/app/output_file.h"

namespace hd::station {
namespace {

void line(std::FILE* out, const char* name, const render::LatencyStats& s) {
  if (s.count == 0) {
    std::fprintf(out, "  %-24s (no frames)\n", name);
    return;
  }
  std::fprintf(out, "  %-24s p50 %7.2f  p95 %7.2f  p99 %7.2f  max %7.2f ms  (%zu frames)\n", name,
               s.p50_ms, s.p95_ms, s.p99_ms, s.max_ms, s.count);
}

nlohmann::json stats_json(const render::LatencyStats& s) {
  return {{"count", s.count},   {"p50_ms", s.p50_ms}, {"p95_ms", s.p95_ms},
          {"p99_ms", s.p99_ms}, {"max_ms", s.max_ms}, {"mean_ms", s.mean_ms}};
}

void print_stages(std::FILE* out, const std::string& source, const std::vector<StageFigure>& st) {
  if (st.empty()) return;
  std::string text;
  for (const StageFigure& f : st) {
    char part[64];
    std::snprintf(part, sizeof part, "%s%s %.1f", text.empty() ? "" : " > ", f.stage.c_str(),
                  f.p50_ms);
    text += part;
  }
  std::fprintf(out, "  stages %-20s p50 ms since capture: %s\n", source.c_str(), text.c_str());
}

nlohmann::json stages_json(const std::vector<StageFigure>& st) {
  nlohmann::json j = nlohmann::json::object();
  for (const StageFigure& f : st) j[f.stage] = f.p50_ms;
  return j;
}

}  // namespace

void print_summary(const RunSummary& s, std::FILE* out) {
  std::fprintf(out, "summary (%s)\n", s.source.c_str());
  std::fprintf(out,
               "  frames %" PRIu64
               " in %.1f s, display %.1f Hz (rate policy %s); missed "
               "deadlines %" PRIu64
               " (%.2f %%) against the rate each frame ran at, skipped "
               "display slots %" PRIu64 "\n",
               s.frames, s.seconds, s.rate_hz, s.rate_policy.c_str(), s.missed_deadlines,
               100.0 * s.missed_rate(), s.skipped_slots);
  for (const HeldRate& r : s.rates)
    std::fprintf(out, "    at %5.1f Hz: %" PRIu64 " frames, %" PRIu64 " missed (%.2f %%)\n",
                 r.rate_hz, r.frames, r.missed_deadlines,
                 r.frames ? 100.0 * double(r.missed_deadlines) / double(r.frames) : 0.0);
  if (s.rate_changes) std::fprintf(out, "    rate changes: %" PRIu64 "\n", s.rate_changes);
  line(out, "motion-to-photon swap", s.mtp_swap);
  line(out, "motion-to-photon display", s.mtp_display);
  line(out, "video age", s.video_age);
  line(out, "model age", s.model_age);
  line(out, "render (draw)", s.render);
  std::fprintf(out,
               "  variants: video %" PRIu64 ", hybrid %" PRIu64 ", synthetic %" PRIu64
               " frames; guidance shown %" PRIu64 " frames; camera switches %" PRIu64 "\n",
               s.variant_frames[0], s.variant_frames[1], s.variant_frames[2], s.guidance_frames,
               s.camera_switches);
  for (const RunSummary::Camera& c : s.cameras)
    std::fprintf(out,
                 "  camera %-20s new frames shown %" PRIu64 ", lost by the device %" PRIu64
                 ", rejected %" PRIu64 "\n",
                 c.name.c_str(), c.frames_shown, c.frames_lost, c.frames_rejected);
  print_stages(out, "model", s.model_stages);
  for (const RunSummary::Camera& c : s.cameras) print_stages(out, c.name, c.stages);
  for (const RunSummary::Camera& c : s.cameras) {
    if (!c.network) continue;
    const RunSummary::NetworkCamera& n = *c.network;
    std::fprintf(out,
                 "  network camera %-12s %" PRIu64 " packets (%" PRIu64
                 " malformed), security %s: %" PRIu64 " rejected; frames with capture time %" PRIu64
                 ", with arrival time %" PRIu64 "; PLI %" PRIu64 ", NACK %" PRIu64
                 ", RTX received %" PRIu64 ", rebuilt from FEC %" PRIu64 ", lost %" PRIu64
                 "; view feedback %" PRIu64 " sent, need changed %" PRIu64 "%s%s\n",
                 c.name.c_str(), n.packets, n.malformed, n.security.c_str(), n.srtp_rejected,
                 n.frames_stamped, n.frames_unstamped, n.pli_sent, n.nack_sent, n.rtx_received,
                 n.fec_recovered, n.lost, n.view_feedback_sent, n.need_changes,
                 n.last_error.empty() ? "" : "; last error: ", n.last_error.c_str());
    std::fprintf(out, "  network camera %-12s clock: %s; %" PRIu64 " capture times after arrival\n",
                 c.name.c_str(), n.clock_text.c_str(), n.capture_after_arrival);
    std::fprintf(out,
                 "  network camera %-12s receive buffer %s; dropped: %s by the kernel (its buffer "
                 "full), %" PRIu64 " late and %" PRIu64
                 " over its latency by the jitter buffer; %" PRIu64 " frames decoded, %" PRIu64
                 " converted\n",
                 c.name.c_str(), n.receive_buffer.c_str(),
                 n.kernel_drops >= 0 ? std::to_string(n.kernel_drops).c_str() : "unknown",
                 n.jitter_too_late, n.jitter_over_latency, n.frames_decoded, n.frames_converted);
    std::fprintf(out,
                 "  network camera %-12s calibration: %s; %" PRIu64
                 " calibration elements refused, %" PRIu64 " frames not shown for want of one\n",
                 c.name.c_str(), n.calibration.c_str(), n.calibration_errors,
                 n.frames_uncalibrated);
  }
  for (const RunSummary::Camera& c : s.cameras) {
    double total_s = 0.0;
    for (const UnusableInterval& u : c.unusable)
      total_s += (u.to_s >= 0.0 ? u.to_s : s.seconds) - u.from_s;
    if (!c.unusable.empty())
      std::fprintf(out, "  camera %-20s unusable %zu times, %.2f s in all (video withheld)\n",
                   c.name.c_str(), c.unusable.size(), total_s);
  }
  std::fprintf(out,
               "  frames with a camera's video withheld as too old or not streaming: %" PRIu64 "\n",
               s.frames_stale_blocked);
  if (!s.camera_events.empty())
    std::fprintf(out, "  camera events (format, calibration from the stream): %zu\n",
                 s.camera_events.size());
  for (const CameraEventRecord& e : s.camera_events)
    std::fprintf(out, "  %s\n", CameraEventLog::line(e).c_str() + 2);
  std::fprintf(out,
               "  head samples accepted %" PRIu64 ", rejected %" PRIu64 "; re-centres %" PRIu64
               ", tracker resets %" PRIu64 "; model updates %" PRIu64 "\n",
               s.pose_accepted, s.pose_rejected, s.recentres, s.tracker_resets, s.model_updates);
  if (s.reconstructions + s.reconstructions_refused > 0)
    std::fprintf(out, "  stereo reconstructions %" PRIu64 ", refused %" PRIu64 "\n",
                 s.reconstructions, s.reconstructions_refused);
  if (!s.cameras_from.empty())
    std::fprintf(out, "  cameras from the network: %s (camera i on PORT + 2 i)%s%s\n",
                 s.cameras_from.c_str(), s.scene_epoch.empty() ? "" : "; scene epoch ",
                 s.scene_epoch.c_str());
  std::fprintf(out, "  render-thread allocations after %" PRIu64 " warm-up frames: %" PRIu64 "\n",
               s.warmup_frames, s.allocations_after_warmup);
  std::fprintf(out,
               "  recorded: video %" PRIu64 " frames, PNG %" PRIu64 " frames, %" PRIu64
               " frames not taken by the writer; frames.csv %" PRIu64 " rows (%" PRIu64
               " beyond its capacity)\n",
               s.video_frames, s.png_frames, s.recorder_dropped, s.log_rows, s.log_rows_dropped);
  if (!s.recorder_error.empty())
    std::fprintf(out, "  recorder error: %s\n", s.recorder_error.c_str());
  for (const std::string& o : s.outputs) std::fprintf(out, "  wrote %s\n", o.c_str());
  std::fflush(out);
}

void write_summary_json(const RunSummary& s, const std::string& path) {
  nlohmann::json j;
  j["source"] = s.source;
  j["frames"] = s.frames;
  j["seconds"] = s.seconds;
  j["rate_hz"] = s.rate_hz;
  j["missed_deadlines"] = s.missed_deadlines;
  j["missed_deadline_rate"] = s.missed_rate();
  j["skipped_slots"] = s.skipped_slots;
  j["rate_policy"] = s.rate_policy;
  j["rate_changes"] = s.rate_changes;
  j["rates"] = nlohmann::json::array();
  for (const HeldRate& r : s.rates)
    j["rates"].push_back(
        {{"rate_hz", r.rate_hz}, {"frames", r.frames}, {"missed_deadlines", r.missed_deadlines}});
  j["latency"] = {{"motion_to_photon_swap", stats_json(s.mtp_swap)},
                  {"motion_to_photon_display", stats_json(s.mtp_display)},
                  {"video_age", stats_json(s.video_age)},
                  {"model_age", stats_json(s.model_age)},
                  {"render", stats_json(s.render)}};
  j["variant_frames"] = {{"video", s.variant_frames[0]},
                         {"hybrid", s.variant_frames[1]},
                         {"synthetic", s.variant_frames[2]}};
  j["guidance_frames"] = s.guidance_frames;
  j["camera_switches"] = s.camera_switches;
  nlohmann::json cams = nlohmann::json::array();
  for (const RunSummary::Camera& c : s.cameras) {
    nlohmann::json unusable = nlohmann::json::array();
    for (const UnusableInterval& u : c.unusable)
      unusable.push_back(
          {{"from_s", u.from_s},
           {"to_s", u.to_s >= 0.0 ? nlohmann::json(u.to_s) : nlohmann::json()},
           {"from_frame", u.from_frame},
           {"to_frame", u.to_s >= 0.0 ? nlohmann::json(u.to_frame) : nlohmann::json()},
           {"video_age_ms", u.age_at_start_ms},
           {"first_new_frame_ns", u.first_new_frame_ns},
           {"usable_again_display_ns", u.to_display_ns},
           {"state", u.state}});
    cams.push_back({{"name", c.name},
                    {"frames_shown", c.frames_shown},
                    {"frames_lost", c.frames_lost},
                    {"frames_rejected", c.frames_rejected},
                    {"stages_p50_ms_since_capture", stages_json(c.stages)},
                    {"unusable_intervals", unusable}});
  }
  j["cameras"] = cams;
  j["model_stages_p50_ms_since_capture"] = stages_json(s.model_stages);
  j["frames_stale_blocked"] = s.frames_stale_blocked;
  nlohmann::json events = nlohmann::json::array();
  for (const CameraEventRecord& e : s.camera_events)
    events.push_back({{"camera", e.camera},
                      {"kind", e.kind},
                      {"cause", e.cause},
                      {"time_ns", e.time_ns},
                      {"t_s", e.t_s},
                      {"expected", e.expected},
                      {"seen", e.seen}});
  j["camera_events"] = events;
  nlohmann::json network = nlohmann::json::array();
  for (const RunSummary::Camera& c : s.cameras) {
    if (!c.network) continue;
    const RunSummary::NetworkCamera& n = *c.network;
    nlohmann::json malformed_by_reason = nlohmann::json::object();
    for (const auto& [reason, count] : n.malformed_by_reason) malformed_by_reason[reason] = count;
    network.push_back({{"camera", c.name},
                       {"security", n.security},
                       {"packets", n.packets},
                       {"bytes", n.bytes},
                       {"malformed_packets", n.malformed},
                       {"malformed_by_reason", malformed_by_reason},
                       {"srtp_rejected_packets", n.srtp_rejected},
                       {"frames_with_capture_time", n.frames_stamped},
                       {"frames_with_arrival_time", n.frames_unstamped},
                       {"frames_not_newer_dropped", n.not_newer},
                       {"bus_errors", n.bus_errors},
                       {"pli_sent", n.pli_sent},
                       {"nack_sent", n.nack_sent},
                       {"rtx_received", n.rtx_received},
                       {"fec_recovered", n.fec_recovered},
                       {"packets_lost", n.lost},
                       {"view_feedback_sent", n.view_feedback_sent},
                       {"need_changes", n.need_changes},
                       {"last_error", n.last_error}});
    nlohmann::json& last = network.back();
    last["clock"] = {{"mapping", n.clock_mapping},
                     {"text", n.clock_text},
                     {"sites_offset_ns", n.clock_sites_offset_ns},
                     {"offset_ns", n.clock_offset_ns},
                     {"uncertainty_ns", n.clock_uncertainty_ns},
                     {"round_trip_ns", n.clock_round_trip_ns},
                     {"samples", n.clock_samples},
                     {"sender_reports", n.sender_reports},
                     {"capture_after_arrival", n.capture_after_arrival}};
    last["receive"] = {{"buffer_asked_bytes", n.receive_buffer_asked},
                       {"buffer_bytes", n.receive_buffer_bytes},
                       {"rmem_max_bytes", n.rmem_max_bytes},
                       {"rtcp_buffer_asked_bytes", n.rtcp_buffer_asked},
                       {"rtcp_buffer_bytes", n.rtcp_buffer_bytes},
                       {"buffer", n.receive_buffer},
                       {"kernel_drops", n.kernel_drops},
                       {"jitter_buffer_too_late", n.jitter_too_late},
                       {"jitter_buffer_over_latency", n.jitter_over_latency},
                       {"frames_decoded", n.frames_decoded},
                       {"frames_converted", n.frames_converted}};
    last["calibration"] = n.calibration;
    last["calibration_errors"] = n.calibration_errors;
    last["frames_uncalibrated"] = n.frames_uncalibrated;
  }
  j["network_cameras"] = network;
  j["head"] = {{"accepted", s.pose_accepted},
               {"rejected", s.pose_rejected},
               {"recentres", s.recentres},
               {"tracker_resets", s.tracker_resets}};
  j["model_updates"] = s.model_updates;
  j["reconstructions"] = s.reconstructions;
  j["reconstructions_refused"] = s.reconstructions_refused;
  // Where the cameras came from and the scene clock (the two-process demo: docs/network.md).
  j["cameras_from"] = s.cameras_from.empty() ? nlohmann::json() : nlohmann::json(s.cameras_from);
  j["scene_epoch"] = s.scene_epoch.empty() ? nlohmann::json() : nlohmann::json(s.scene_epoch);
  j["first_frame_scene_s"] = s.first_frame_scene_s;
  j["allocations_after_warmup"] = s.allocations_after_warmup;
  j["warmup_frames"] = s.warmup_frames;
  j["frames_csv_rows"] = s.log_rows;
  j["frames_csv_rows_dropped"] = s.log_rows_dropped;
  j["video_frames"] = s.video_frames;
  j["png_frames"] = s.png_frames;
  j["recorder_dropped"] = s.recorder_dropped;
  j["recorder_error"] = s.recorder_error;
  write_text_atomically(j.dump(1) + "\n", path);
}

}  // namespace hd::station
