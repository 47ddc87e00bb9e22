#include "vid_system/outputs.h"

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

namespace vid::system {

FlushedFile::FlushedFile(const std::filesystem::path& path) : path_(path) {
  f_ = std::fopen(path.c_str(), "w");
  if (f_ == nullptr) {
    throw std::runtime_error(fmt::format("{}: cannot open for writing: {}", path.string(), std::strerror(errno)));
  }
}

FlushedFile::~FlushedFile() {
  if (f_ != nullptr) std::fclose(f_);
}

void FlushedFile::line(const std::string& text) {
  if (f_ == nullptr) return;
  if (std::fputs(text.c_str(), f_) < 0 || std::fputc('\n', f_) == EOF || std::fflush(f_) != 0) {
    throw std::runtime_error(fmt::format("{}: write failed: {}", path_.string(), std::strerror(errno)));
  }
}

void FlushedFile::close() {
  if (f_ != nullptr) {
    const int rc = std::fclose(f_);
    f_ = nullptr;
    if (rc != 0) throw std::runtime_error(fmt::format("{}: close failed: {}", path_.string(), std::strerror(errno)));
  }
}

std::string state_csv_header() {
  // Same column names as vid_eval.formats.STATE_COLUMNS (the Python loader checks them).
  return "#timestamp [ns],p_x [m],p_y [m],p_z [m],q_w [],q_x [],q_y [],q_z [],v_x [m s^-1],v_y [m s^-1],"
         "v_z [m s^-1],bg_x [rad s^-1],bg_y [rad s^-1],bg_z [rad s^-1],ba_x [m s^-2],ba_y [m s^-2],"
         "ba_z [m s^-2],f_x [m s^-2],f_y [m s^-2],f_z [m s^-2],"
         "sigma_theta_x [rad],sigma_theta_y [rad],sigma_theta_z [rad],sigma_p_x [m],sigma_p_y [m],sigma_p_z [m],"
         "sigma_v_x [m s^-1],sigma_v_y [m s^-1],sigma_v_z [m s^-1],sigma_bg_x [rad s^-1],"
         "sigma_bg_y [rad s^-1],sigma_bg_z [rad s^-1],sigma_ba_x [m s^-2],sigma_ba_y [m s^-2],"
         "sigma_ba_z [m s^-2],sigma_f_x [m s^-2],sigma_f_y [m s^-2],sigma_f_z [m s^-2]";
}

std::string force_csv_header() {
  return "#timestamp [ns],fb_x [m s^-2],fb_y [m s^-2],fb_z [m s^-2],fw_x [m s^-2],fw_y [m s^-2],"
         "fw_z [m s^-2],sigma_x [m s^-2],sigma_y [m s^-2],sigma_z [m s^-2]";
}

std::string mass_csv_header() {
  // The mass-estimate format vid-eval mass reads (docs/formats.md): timestamp, mass, sigma.
  return "#timestamp [ns],mass [kg],sigma [kg]";
}

std::string mass_csv_line(const EstimateRow& r, double mass_kg) {
  // m = m0 / s, sigma_m = m0 sigma_s / s^2 (first order).
  const double s = r.thrust_scale;
  return fmt::format("{},{:.9g},{:.6g}", r.t_ns, mass_kg / s, mass_kg * r.sigma_thrust_scale / (s * s));
}

std::string timing_csv_header() {
  return "#timestamp [ns],tracking [ms],propagation [ms],accel_updates [ms],msckf_update [ms],"
         "marginalization [ms],total [ms]";
}

std::string tracks_csv_header() { return "#timestamp [ns],cam_id,feature_id,u [px],v [px]"; }

std::string tracks_csv_row(TimeNs t_ns, const FeatureObservation& ob) {
  return fmt::format("{},{},{},{:.4f},{:.4f}", t_ns, ob.cam_id, ob.feature_id, ob.uv.x(), ob.uv.y());
}

RunOutputs::RunOutputs(const std::filesystem::path& out_dir, bool write_force, std::optional<double> mass_kg,
                       bool time_offset)
    : write_force_(write_force),
      mass_kg_(mass_kg),
      tum_(out_dir / "trajectory_tum.txt"),
      state_(out_dir / "state.csv"),
      force_(out_dir / "force.csv"),
      timing_(out_dir / "timing.csv") {
  tum_.line("# timestamp tx ty tz qx qy qz qw");
  state_.line(state_csv_header());
  force_.line(force_csv_header());
  timing_.line(timing_csv_header());
  if (mass_kg_) {
    mass_.emplace(out_dir / "mass.csv");
    mass_->line(mass_csv_header());
  }
  if (time_offset) {
    time_offset_.emplace(out_dir / "time_offset.csv");
    time_offset_->line("#timestamp [ns],time_offset [s],sigma [s]");
  }
}

std::string tum_reinit_marker(TimeNs t_ns) {
  return fmt::format("{} {}.{:09d}: a new world frame from here on", kTumReinitMarker, t_ns / 1000000000,
                     t_ns % 1000000000);
}

void RunOutputs::mark_reinitialization(TimeNs t_ns) { tum_.line(tum_reinit_marker(t_ns)); }

void RunOutputs::write_pose(const TimedPose& pose) { tum_.line(tum_line(pose)); }

std::string tum_line(const TimedPose& x) {
  const Eigen::Quaterniond q = x.T.q.normalized();
  // Seconds with 9 decimals from integer ns, so no precision is lost.
  const TimeNs sec = x.t_ns / 1000000000;
  const TimeNs frac = x.t_ns % 1000000000;
  return fmt::format("{}.{:09d} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f}", sec, frac, x.T.p.x(), x.T.p.y(),
                     x.T.p.z(), q.x(), q.y(), q.z(), q.w());
}

void RunOutputs::write_estimate(const EstimateRow& r) {
  const Eigen::Quaterniond q = r.T_WI.q.normalized();
  tum_.line(tum_line({r.t_ns, r.T_WI}));
  std::string row = fmt::format("{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}", r.t_ns, r.T_WI.p.x(), r.T_WI.p.y(),
                                r.T_WI.p.z(), q.w(), q.x(), q.y(), q.z());
  auto append3 = [&row](const Eigen::Vector3d& v) { row += fmt::format(",{:.9g},{:.9g},{:.9g}", v.x(), v.y(), v.z()); };
  append3(r.v_WI);
  append3(r.b_g);
  append3(r.b_a);
  append3(r.F_ext_I);
  for (int i = 0; i < 18; ++i) row += fmt::format(",{:.6g}", r.sigma(i));
  state_.line(row);
  if (write_force_) force_.line(force_csv_line(r));
  if (mass_) mass_->line(mass_csv_line(r, *mass_kg_));
  if (time_offset_) time_offset_->line(fmt::format("{},{:.9g},{:.6g}", r.t_ns, r.time_offset_s, r.sigma_time_offset_s));
}

std::string force_csv_line(const EstimateRow& r) {
  const Eigen::Vector3d f_W = r.T_WI.q.normalized() * r.F_ext_I;
  return fmt::format("{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.6g},{:.6g},{:.6g}", r.t_ns, r.F_ext_I.x(),
                     r.F_ext_I.y(), r.F_ext_I.z(), f_W.x(), f_W.y(), f_W.z(), r.sigma(15), r.sigma(16), r.sigma(17));
}

void RunOutputs::write_timing(const TimingRow& t) {
  timing_.line(fmt::format("{},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f}", t.t_ns, t.tracking_ms, t.propagation_ms,
                           t.accel_update_ms, t.msckf_update_ms, t.marginalization_ms, t.total_ms));
}

void RunOutputs::close() {
  tum_.close();
  state_.close();
  force_.close();
  timing_.close();
  if (mass_) mass_->close();
  if (time_offset_) time_offset_->close();
}

SmoothedOutputs::SmoothedOutputs(const std::filesystem::path& out_dir)
    : tum_(out_dir / "trajectory_smoothed_tum.txt"), force_(out_dir / "force_smoothed.csv") {
  tum_.line("# timestamp tx ty tz qx qy qz qw");
  force_.line(force_csv_header());
}

void SmoothedOutputs::write_estimate(const EstimateRow& r) {
  tum_.line(tum_line({r.t_ns, r.T_WI}));
  force_.line(force_csv_line(r));
}

void SmoothedOutputs::mark_reinitialization(TimeNs t_ns) { tum_.line(tum_reinit_marker(t_ns)); }

void SmoothedOutputs::close() {
  tum_.close();
  force_.close();
}

}  // namespace vid::system
