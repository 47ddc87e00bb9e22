// System::summary(): summary.json's fields of a run (docs/formats.md §2), with the metrics
// against the ground truth pushed.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "vid_system/system.h"
#include "vid_version/version.h"

namespace vid::system {

nlohmann::json noise_fit_report(const EstimatorCounters& c) {
  // A consistent filter's normalized innovations average 1 (per accelerometer axis; per degree
  // of freedom of the features used, a little below 1 as the 95 % gate cuts the tail). Above 3
  // the noise setting is overconfident and the estimate suffers: one warning line naming the key.
  // Below 1/3 it is only pessimistic (config/sim's 0.5 px on rendered images whose KLT tracks are
  // good to 0.04 px, on purpose): summary.json says so, no warning.
  constexpr double kFactor = 3.0;
  nlohmann::json j;
  nlohmann::json warnings = nlohmann::json::array();
  if (c.accel_nis_count > 0) {
    const Eigen::Vector3d nis = c.accel_nis_sum / static_cast<double>(c.accel_nis_count);
    j["accel_nis_per_axis"] = {nis.x(), nis.y(), nis.z()};
    j["accel_samples"] = c.accel_nis_count;
    // The share of samples whose noise the vibration-aware adaptation raised (accel_noise.h).
    j["accel_noise_inflated_fraction"] = static_cast<double>(c.accel_noise_inflated) / static_cast<double>(c.accel_nis_count);
    const char* axes = "xyz";
    for (int i = 0; i < 3; ++i) {
      if (nis(i) > kFactor)
        warnings.push_back(fmt::format("accelerometer innovations on the IMU {} axis average {:.2f} times their modeled "
                                       "variance (1 fits): raise accel_noise_density (imu0/sensor.yaml; measure it in "
                                       "flight: vid-allan --flight) or thrust_noise_density",
                                       axes[i], nis(i)));
    }
  }
  if (c.visual_dof_sum > 0) {
    const double per_dof = c.visual_chi2_sum / static_cast<double>(c.visual_dof_sum);
    j["visual_chi2_per_dof"] = per_dof;
    j["visual_dof"] = c.visual_dof_sum;
    if (per_dof > kFactor)
      warnings.push_back(fmt::format("visual feature residuals average {:.2f} times their modeled variance per degree of "
                                     "freedom (1 fits): raise pixel_noise_px", per_dof));
  }
  j["warnings"] = warnings;
  return j;
}

nlohmann::json flight_phase_report(const EstimatorCounters& c, FlightPhase now) {
  nlohmann::json j;
  j["final"] = to_string(now);
  j["landed_s"] = c.landed_s;
  j["airborne_s"] = c.airborne_s;
  long lift_offs = 0, touchdowns = 0;
  nlohmann::json events = nlohmann::json::array();
  for (const FlightPhaseRecord& r : c.flight_phase_events) {
    const bool lift_off = r.to == FlightPhase::kAirborne;
    (lift_off ? lift_offs : touchdowns) += 1;
    if (events.size() < 200) events.push_back({{"t_ns", r.t_ns}, {"event", lift_off ? "lift_off" : "touchdown"}});
  }
  j["lift_offs"] = lift_offs;
  j["touchdowns"] = touchdowns;
  j["events"] = events;
  return j;
}

nlohmann::json accel_report(const EstimatorCounters& c) {
  nlohmann::json j;
  const long seen = c.accel_updates + c.accel_rejected + c.accel_downweighted + c.accel_used_in_jumps;
  j["samples"] = seen;
  j["rejected"] = c.accel_rejected;
  j["rejected_fraction"] = seen > 0 ? static_cast<double>(c.accel_rejected) / static_cast<double>(seen) : 0.0;
  j["used_in_jumps"] = c.accel_used_in_jumps;
  j["force_jumps"] = c.force_jumps;
  const auto add_spans = [&j](const std::string& key, const std::vector<TimeSpan>& spans) {
    double total_s = 0.0;
    nlohmann::json list = nlohmann::json::array();
    for (const TimeSpan& s : spans) {
      total_s += static_cast<double>(s.last_ns - s.first_ns) * 1e-9;
      if (list.size() < 200) list.push_back({s.first_ns, s.last_ns});
    }
    j[key + "_spans_ns"] = list;
    j[key + "_span_count"] = spans.size();
    j[key + "_span_total_s"] = total_s;
  };
  add_spans("rejected", c.accel_rejected_spans);
  j["downweighted"] = c.accel_downweighted;
  j["downweighted_fraction"] =
      seen > 0 ? static_cast<double>(c.accel_downweighted) / static_cast<double>(seen) : 0.0;
  add_spans("downweighted", c.accel_downweighted_spans);
  nlohmann::json jumps = nlohmann::json::array();
  for (const ForceJumpRecord& r : c.force_jump_events) {
    if (jumps.size() >= 200) break;
    jumps.push_back({{"t_ns", r.t_ns}, {"window", r.window}, {"size_mps2", r.size_mps2}});
  }
  j["force_jump_events"] = jumps;
  return j;
}

EstimatorCounters System::counters() const {
  EstimatorCounters c = past_counters_;
  c.merge(estimator_->counters());
  return c;
}

namespace {
// A world-frame series rotated piece by piece with each piece's alignment yaw.
Vec3Series rotate_pieces(const Vec3Series& f_W, const SegmentedAte& seg) {
  Vec3Series out;
  for (std::size_t k = 0; k < seg.segments.size(); ++k) {
    const TimeNs t0 = k == 0 ? INT64_MIN : seg.t_start_ns[k];
    const TimeNs t1 = k + 1 < seg.segments.size() ? seg.t_start_ns[k + 1] : INT64_MAX;
    const Vec3Series piece = rotate_about_z(slice(f_W, t0, t1), seg.segments[k].yaw_rad);
    out.t_ns.insert(out.t_ns.end(), piece.t_ns.begin(), piece.t_ns.end());
    out.v.insert(out.v.end(), piece.v.begin(), piece.v.end());
  }
  return out;
}
}  // namespace

void System::score(nlohmann::json& s, const Vec3Series& est_p, const Vec3Series& est_f_W, const Vec3Series& est_f_I,
                   const std::string& sfx) const {
  // After a re-initialization the estimator has a new world frame: each piece between two
  // initializations is aligned on its own (docs/notes/recovery.md).
  // A piece after a re-initialization starts with its first output (the in-flight initializer's
  // window, when it wrote one), the first piece at the first initialization.
  std::vector<TimeNs> starts;
  const EstimatorCounters c = counters();
  if (!c.inits.empty()) starts.push_back(c.inits.front().t_ns);
  starts.insert(starts.end(), piece_starts_.begin(), piece_starts_.end());
  std::optional<SegmentedAte> seg;
  if (!gt_p_.t_ns.empty()) seg = ate_posyaw_segments(est_p, gt_p_, starts);
  std::optional<AteResult> ate;
  if (seg) ate = seg->pooled;
  if (ate) {
    s["ate_posyaw_m" + sfx] = ate->rmse_m;
    s["ate_pairs" + sfx] = ate->pairs;
  }
  if (seg && seg->segments.size() > 1) {
    nlohmann::json pieces = nlohmann::json::array();
    for (std::size_t k = 0; k < seg->segments.size(); ++k)
      pieces.push_back({{"t_start_ns", seg->t_start_ns[k]}, {"ate_posyaw_m", seg->segments[k].rmse_m},
                        {"pairs", seg->segments[k].pairs}, {"yaw_deg", seg->segments[k].yaw_rad * 180.0 / M_PI}});
    s["ate_segments" + sfx] = pieces;
  }
  const auto& truth_vehicle = p_.truth_vehicle;
  if (dynamics() && !gt_f_W_.t_ns.empty() && (!mass_t_.empty() || truth_vehicle)) {
    Vec3Series gt_f = gt_f_W_;
    for (std::size_t i = 0; i < gt_f.t_ns.size(); ++i) {
      const double m = mass_t_.empty() ? truth_vehicle->mass_kg : mass_at(mass_t_, mass_kg_, gt_f.t_ns[i]);
      gt_f.v[i] /= m;
    }
    // The estimator's world has its own heading (yaw is unobservable): the world-frame figure
    // is taken after rotating the estimate by the ATE's alignment, never without one.
    std::size_t pairs = 0;
    if (!ate) {
      s["force_rmse_world_note" + sfx] = "no ground-truth poses to align the estimator's world frame: world-frame force not scored";
    } else if (auto rmse = force_rmse(rotate_pieces(est_f_W, *seg), gt_f, &pairs)) {
      s["force_rmse_world_mps2" + sfx] = *rmse;
      s["force_pairs" + sfx] = pairs;
      s["force_alignment" + sfx] = {{"mode", "posyaw"}, {"yaw_deg", ate->yaw_rad * 180.0 / M_PI}};
    }
    if (!gt_R_WI_.empty()) {
      if (auto rmse = force_rmse(est_f_I, world_to_body(gt_f, gt_p_.t_ns, gt_R_WI_)))
        s["force_rmse_body_mps2" + sfx] = *rmse;
    }
  }
}

nlohmann::json System::summary() const {
  const SystemConfig& cfg = p_.config;
  nlohmann::json s;
  s["version"] = {{"vid_msckf", version()}, {"git", git_sha()}};
  s["mode"] = to_string(cfg.estimator.mode);
  s["mode_source"] = p_.mode_source;
  if (p_.ignore_rotor_speeds) s["thrust_source"] = "thrust0 (rotor0 present, not used)";
  s["init"] = to_string(cfg.estimator.init_mode);
  s["features"] = p_.features == FeatureSource::kFeat0 ? "feat0" : "images";
  s["status"] = to_string(estimator_->status());
  s["status_message"] = estimator_->status_message();
  const EstimatorCounters c = counters();
  {  // docs/notes/initialization.md: every (re-)initialization, how and when
    nlohmann::json events = nlohmann::json::array();
    for (const InitRecord& r : c.inits)
      if (events.size() < 200) events.push_back({{"t_ns", r.t_ns}, {"how", r.how}});
    s["initializations"] = {{"count", c.inits.size()},
                            {"reinitializations", c.inits.empty() ? 0 : c.inits.size() - 1},
                            {"events", events}};
  }
  s["counts"] = {{"estimates", estimates_},
                 {"camera_frames", frames_},
                 {"feature_frames", feature_frames_},
                 {"images_missing", faults_.missing()},
                 {"images_unreadable", faults_.unreadable()},
                 {"images_wrong_size", faults_.wrong_size()},
                 {"frames_skipped_bad_image", faults_.total()},
                 {"imu_samples", c.imu_samples},
                 {"accel_updates", c.accel_updates},
                 {"accel_rejected", c.accel_rejected},
                 {"accel_downweighted", c.accel_downweighted},
                 {"accel_used_in_jumps", c.accel_used_in_jumps},
                 {"force_jumps", c.force_jumps},
                 {"rotor_gap_samples", c.rotor_gap_samples},
                 {"imu_gaps", c.imu_gaps},
                 {"frames_processed", c.frames},
                 {"frames_skipped_by_filter", c.frames_skipped},
                 {"visual_updates", c.visual_updates},
                 {"features_used", c.features_used},
                 {"features_rejected", c.features_rejected},
                 {"features_rejected_chi2", c.features_rejected_chi2},
                 {"zero_velocity_updates", c.zero_velocity_updates},
                 {"zero_velocity_updates_landed", c.zero_velocity_updates_landed}};
  if (restarts_ > 0) s["counts"]["estimator_restarts"] = restarts_;
  s["health"] = {{"starvation_episodes", c.starvation_episodes},
                 {"starved_s", c.starved_s},
                 {"max_chi2_rejected_fraction", c.max_chi2_rejected_fraction}};
  s["accel"] = accel_report(c);
  s["noise_fit"] = noise_fit_report(c);
  add_force_check(s, force_mag_, cfg.estimator.gravity);  // named warnings in s["warnings"]
  if (dynamics()) s["flight_phase"] = flight_phase_report(c, estimator_->flight_phase());
  s["timing"] = stage_times_.to_json();  // frontend + estimator stages; excludes image decoding
  s["timing"]["image_decoding"] = decode_ms_.to_json();
  s["peak_memory_mib"] = peak_memory_mib();
  // CPU-time view (robust to other processes on a shared machine); the caller adds the
  // CPU real-time factor, which needs the data duration.
  const double cpu_s = process_cpu_s() - cpu_start_s_;
  s["cpu"]["process_cpu_s"] = cpu_s;
  s["cpu"]["image_decoding_cpu_s"] = decode_cpu_ms_ * 1e-3;
  s["cpu"]["tracking_cpu"] = tracking_cpu_ms_.to_json();
  s["cpu"]["mean_cpu_ms_per_frame_excluding_decoding"] =
      c.frames > 0 ? (cpu_s * 1e3 - decode_cpu_ms_) / static_cast<double>(c.frames) : 0.0;
  s["config"] = describe_json(cfg);
  s["config_yaml"] = describe(cfg);  // the same, as the YAML files read
  s["config_sources"] = cfg.sources;
  s["config_overrides"] = cfg.overrides;

  // Metrics against ground truth, with the association and alignment of vid_eval; with
  // fixed-lag smoothing the same figures of the smoothed outputs, keys suffixed "_smoothed".
  score(s, est_p_, est_f_W_, est_f_I_, "");
  if (smoothing()) score(s, est_p_smoothed_, est_f_W_smoothed_, est_f_I_smoothed_, "_smoothed");
  return s;
}

}  // namespace vid::system
