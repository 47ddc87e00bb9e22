/// @file system_bindings.cpp
/// @brief Python bindings of vid::system::System (push-style) and of its dataset run (vid_system/dataset_run.h, as vid_run).
///
/// numpy in and out: samples are pushed one at a time or as arrays (IMU), images as uint8
/// arrays; the estimates come back as numpy arrays (history()) or as one dict (latest()).
/// The GIL is released while C++ works (frontend, filter, a whole dataset run), never while a
/// Python object is touched.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include "io/dataset_reader.h"
#include "io/errors.h"
#include "vid_system/dataset_run.h"
#include "vid_system/summary.h"
#include "vid_system/system.h"
#include "vid_version/version.h"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace vid::python {
namespace {

/// JSON -> Python objects through the json module (summary.json as a dict, exactly as written).
py::object to_python(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

system::FeatureSource feature_source(const std::string& s) {
  if (s == "images") return system::FeatureSource::kImages;
  if (s == "feat0") return system::FeatureSource::kFeat0;
  if (s == "auto") return system::FeatureSource::kAuto;
  throw py::value_error("features must be 'images', 'feat0' or 'auto', not '" + s + "'");
}

/// A uint8 (H, W) array as a cv::Mat that shares its memory (valid while the array lives).
cv::Mat gray8_view(const py::array& a, const char* name) {
  if (a.ndim() != 2 || !py::isinstance<py::array_t<std::uint8_t>>(a))
    throw py::type_error(std::string(name) + " must be a 2-D uint8 array (gray image), got ndim " +
                         std::to_string(a.ndim()) + " dtype " + std::string(py::str(a.dtype())));
  auto c = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(a);
  return cv::Mat(static_cast<int>(c.shape(0)), static_cast<int>(c.shape(1)), CV_8UC1,
                 const_cast<std::uint8_t*>(c.data()));
}

Eigen::Vector3d vec3(const Eigen::Ref<const Eigen::VectorXd>& v, const char* name) {
  if (v.size() != 3) throw py::value_error(std::string(name) + " must have 3 elements, got " + std::to_string(v.size()));
  return v;
}

/// Every estimate kept as rows, for history() (IMU rate: ~100 bytes a sample).
struct History {
  std::vector<TimeNs> t_ns;
  std::vector<double> p, q, v, bg, ba, f_I, f_W, sigma;
  int sigma_dim = 0;
  void add(const EstimateOutput& e) {
    const ImuState& x = e.x;
    t_ns.push_back(e.t_ns);
    auto put = [](std::vector<double>& dst, const auto& src) { dst.insert(dst.end(), src.data(), src.data() + src.size()); };
    put(p, x.T_WI.p);
    const Eigen::Quaterniond qn = x.T_WI.q.normalized();
    q.insert(q.end(), {qn.w(), qn.x(), qn.y(), qn.z()});
    put(v, x.v_WI);
    put(bg, x.b_g);
    put(ba, x.b_a);
    put(f_I, e.F_ext_I);
    put(f_W, e.F_ext_W);
    sigma_dim = static_cast<int>(e.sigma.size());
    put(sigma, e.sigma);
  }
};

py::array_t<double> rows(const std::vector<double>& data, std::size_t n, std::size_t cols) {
  return py::array_t<double>(std::vector<py::ssize_t>{static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(cols)},
                             data.data());  // copies
}

/// The estimator as a Python object: a System plus the estimates it produced.
class PySystem {
 public:
  PySystem(std::optional<fs::path> dataset, std::optional<fs::path> config, std::optional<std::string> mode,
           std::optional<std::string> init, std::optional<fs::path> out_dir, const std::string& features,
           std::optional<bool> rotors, std::optional<bool> thrust, bool keep_history) {
    if (!dataset && !config) throw py::value_error("give a dataset folder (its calibration) and/or a config preset folder");
    io::DatasetCalibration calib;
    system::SystemOptions so;
    if (dataset) {
      io::DatasetReader probe(*dataset);
      calib = probe.calibration();
      so.has_rotor = probe.has_stream("rotor0");
      so.has_thrust = probe.has_stream("thrust0");
      so.context = dataset->string();
    } else {
      so.context = config->string();
    }
    if (rotors) so.has_rotor = *rotors;
    if (thrust) so.has_thrust = *thrust;
    so.config = config;
    so.out_dir = out_dir;
    if (mode) so.mode = mode_from_string(*mode);
    if (init) so.init = init_mode_from_string(*init);
    so.features = feature_source(features);
    if (so.features == system::FeatureSource::kAuto) so.features = system::FeatureSource::kImages;
    if (out_dir) fs::create_directories(*out_dir);
    sys_ = std::make_unique<system::System>(system::make_system_params(so, calib));
    latest_.reset();
    sys_->on_estimate([this, keep_history](const EstimateOutput& e) {
      latest_ = e;
      if (keep_history) history_.add(e);
    });
  }

  void push_imu(TimeNs t_ns, const Eigen::Ref<const Eigen::VectorXd>& gyro, const Eigen::Ref<const Eigen::VectorXd>& accel) {
    ImuSample s{t_ns, vec3(gyro, "gyro"), vec3(accel, "accel")};
    py::gil_scoped_release nogil;
    sys_->push(s);
  }

  void push_imu_array(const py::array_t<std::int64_t>& t_ns, const Eigen::Ref<const Eigen::MatrixXd>& gyro,
                      const Eigen::Ref<const Eigen::MatrixXd>& accel) {
    const auto n = static_cast<Eigen::Index>(t_ns.size());
    if (t_ns.ndim() != 1 || gyro.rows() != n || accel.rows() != n || gyro.cols() != 3 || accel.cols() != 3)
      throw py::value_error("push_imu_array: t_ns (N,), gyro (N, 3), accel (N, 3) expected");
    std::vector<ImuSample> samples(static_cast<std::size_t>(n));
    const auto t = t_ns.unchecked<1>();
    for (Eigen::Index i = 0; i < n; ++i)
      samples[static_cast<std::size_t>(i)] = ImuSample{t(i), gyro.row(i).transpose(), accel.row(i).transpose()};
    py::gil_scoped_release nogil;
    for (const auto& s : samples) sys_->push(s);
  }

  void push_rotors(TimeNs t_ns, std::vector<double> speeds) {
    py::gil_scoped_release nogil;
    sys_->push(RotorSample{t_ns, std::move(speeds)});
  }

  void push_thrust(TimeNs t_ns, double thrust_N) {
    py::gil_scoped_release nogil;
    sys_->push(ThrustSample{t_ns, thrust_N});
  }

  void push_images(TimeNs t_ns, const py::array& left, const std::optional<py::array>& right) {
    system::StereoFrame f;
    f.t_ns = t_ns;
    f.left = gray8_view(left, "left");
    if (right) f.right = gray8_view(*right, "right");
    py::gil_scoped_release nogil;  // the arrays stay alive: the caller holds them for this call
    sys_->push(f);
  }

  void push_image_files(TimeNs t_ns, const std::vector<std::string>& paths) {
    ImageFrame f;
    f.t_ns = t_ns;
    for (std::size_t i = 0; i < paths.size(); ++i) f.images.push_back(ImageRef{static_cast<int>(i), paths[i]});
    py::gil_scoped_release nogil;
    sys_->push(f);
  }

  void push_ground_truth(TimeNs t_ns, const Eigen::Ref<const Eigen::VectorXd>& p_WI,
                         const Eigen::Ref<const Eigen::VectorXd>& q_WI_wxyz, const Eigen::Ref<const Eigen::VectorXd>& v_WI) {
    if (q_WI_wxyz.size() != 4) throw py::value_error("q_WI must be 4 numbers (w, x, y, z)");
    GroundTruthSample s;
    s.t_ns = t_ns;
    s.T_WI.p = vec3(p_WI, "p_WI");
    s.T_WI.q = Eigen::Quaterniond(q_WI_wxyz[0], q_WI_wxyz[1], q_WI_wxyz[2], q_WI_wxyz[3]).normalized();
    s.v_WI = vec3(v_WI, "v_WI");
    py::gil_scoped_release nogil;
    sys_->push(s);
  }

  void finish() {
    py::gil_scoped_release nogil;
    sys_->finish();
  }

  /// The newest estimate as a dict (None before the filter initialized).
  py::object latest() const {
    if (!latest_) return py::none();
    const EstimateOutput& e = *latest_;
    const Eigen::Quaterniond q = e.x.T_WI.q.normalized();
    py::dict d;
    d["t_ns"] = e.t_ns;
    d["p_WI"] = Eigen::Vector3d(e.x.T_WI.p);
    d["q_WI"] = Eigen::Vector4d(q.w(), q.x(), q.y(), q.z());
    d["R_WI"] = Eigen::Matrix3d(q.toRotationMatrix());
    d["v_WI"] = Eigen::Vector3d(e.x.v_WI);
    d["b_g"] = Eigen::Vector3d(e.x.b_g);
    d["b_a"] = Eigen::Vector3d(e.x.b_a);
    d["F_ext_I"] = Eigen::Vector3d(e.F_ext_I);
    d["F_ext_W"] = Eigen::Vector3d(e.F_ext_W);
    d["cov_F_I"] = Eigen::Matrix3d(e.cov_F_I);
    d["cov_F_W"] = Eigen::Matrix3d(e.cov_F_W);
    d["cov_theta"] = Eigen::Matrix3d(e.cov_theta);
    d["cov_p"] = Eigen::Matrix3d(e.cov_p);
    d["sigma"] = Eigen::VectorXd(e.sigma);
    d["status"] = to_string(e.status);
    d["force_frame"] = to_string(sys_->config().estimator.force_frame);  // frame of sigma's force block
    return d;
  }

  /// Every estimate as arrays (state.csv's columns).
  py::dict history() const {
    const History& h = history_;
    const std::size_t n = h.t_ns.size();
    py::dict d;
    d["t_ns"] = py::array_t<std::int64_t>(static_cast<py::ssize_t>(n), h.t_ns.data());  // copies
    d["p_WI"] = rows(h.p, n, 3);
    d["q_WI"] = rows(h.q, n, 4);
    d["v_WI"] = rows(h.v, n, 3);
    d["b_g"] = rows(h.bg, n, 3);
    d["b_a"] = rows(h.ba, n, 3);
    d["F_ext_I"] = rows(h.f_I, n, 3);
    d["F_ext_W"] = rows(h.f_W, n, 3);
    d["sigma"] = rows(h.sigma, n, static_cast<std::size_t>(h.sigma_dim));
    return d;
  }

  system::System& sys() { return *sys_; }

 private:
  std::unique_ptr<system::System> sys_;
  std::optional<EstimateOutput> latest_;
  History history_;
};

/// vid_run on a dataset folder; returns summary.json as a dict (status "diverged" / "error" in it).
py::object run_dataset(const fs::path& dataset, const fs::path& out_dir, std::optional<fs::path> config,
                       std::optional<std::string> mode, std::optional<std::string> init, const std::string& features,
                       double start_s, std::optional<double> end_s, bool strict, int decode_threads, bool progress) {
  system::RunOptions o;
  o.dataset = dataset;
  o.out_dir = out_dir;
  o.config = std::move(config);
  if (mode) o.mode = mode_from_string(*mode);
  if (init) o.init = init_mode_from_string(*init);
  o.features = feature_source(features);
  o.start_s = start_s;
  o.end_s = end_s;
  o.strict = strict;
  o.decode_threads = decode_threads;
  o.progress = progress;
  {
    const std::atomic<bool> stop{false};
    py::gil_scoped_release nogil;
    system::run_dataset(o, stop);
  }
  return py::module_::import("json").attr("loads")(
      py::module_::import("pathlib").attr("Path")(out_dir / "summary.json").attr("read_text")());
}

}  // namespace
}  // namespace vid::python

PYBIND11_MODULE(_core, m) {
  using vid::python::PySystem;
  m.doc() = "VID-MSCKF estimator (C++) bindings; see the vid_msckf package docstring.";
  m.attr("__version__") = vid::version();
  m.attr("git_sha") = vid::git_sha();
  py::register_exception<vid::io::ConfigError>(m, "ConfigError", PyExc_ValueError);
  py::register_exception<vid::io::DatasetError>(m, "DatasetError", PyExc_ValueError);

  py::class_<PySystem>(m, "System", "The estimator, fed push-style in time order (vid_system::System).")
      .def(py::init<std::optional<fs::path>, std::optional<fs::path>, std::optional<std::string>,
                    std::optional<std::string>, std::optional<fs::path>, const std::string&, std::optional<bool>,
                    std::optional<bool>, bool>(),
           py::kw_only(), py::arg("dataset") = py::none(), py::arg("config") = py::none(), py::arg("mode") = py::none(),
           py::arg("init") = py::none(), py::arg("out_dir") = py::none(), py::arg("features") = "images",
           py::arg("rotors") = py::none(), py::arg("thrust") = py::none(), py::arg("keep_history") = true,
           "Build from a dataset folder's calibration and/or a config preset folder. mode: 'imu' | "
           "'dynamics' (default: dynamics when rotor speeds or thrust will be pushed: the dataset's "
           "rotor0/thrust0, or rotors=True / thrust=True). out_dir: also write vid_run's files there.")
      .def("push_imu", &PySystem::push_imu, py::arg("t_ns"), py::arg("gyro"), py::arg("accel"),
           "One IMU sample: gyro [rad/s], accel [m/s^2], body frame I.")
      .def("push_imu_array", &PySystem::push_imu_array, py::arg("t_ns"), py::arg("gyro"), py::arg("accel"),
           "N IMU samples: t_ns (N,) int64, gyro (N, 3), accel (N, 3).")
      .def("push_rotors", &PySystem::push_rotors, py::arg("t_ns"), py::arg("speeds"),
           "Rotor speeds in rotor0/sensor.yaml's unit.")
      .def("push_thrust", &PySystem::push_thrust, py::arg("t_ns"), py::arg("thrust_N"), "Collective thrust [N].")
      .def("push_images", &PySystem::push_images, py::arg("t_ns"), py::arg("left"), py::arg("right") = py::none(),
           "A camera frame: uint8 (H, W) arrays (right: None for mono).")
      .def("push_image_files", &PySystem::push_image_files, py::arg("t_ns"), py::arg("paths"),
           "A camera frame by image paths (cam0, cam1), decoded as vid_run decodes them.")
      .def("push_ground_truth", &PySystem::push_ground_truth, py::arg("t_ns"), py::arg("p_WI"), py::arg("q_WI"),
           py::arg("v_WI"), "Ground truth (metrics, --init groundtruth); q_WI as (w, x, y, z).")
      .def("finish", &PySystem::finish, "End of stream: process everything still queued.")
      .def("latest", &PySystem::latest, "The newest estimate as a dict of numpy arrays, None before initialization.")
      .def("history", &PySystem::history, "Every estimate as numpy arrays (t_ns, p_WI, q_WI (w,x,y,z), v_WI, ...).")
      .def("summary", [](PySystem& s) { return vid::python::to_python(s.sys().summary()); },
           "summary.json's fields so far, as a dict.")
      .def_property_readonly("status", [](PySystem& s) { return vid::to_string(s.sys().status()); })
      .def_property_readonly("status_message", [](PySystem& s) { return s.sys().status_message(); })
      .def_property_readonly("force_frame",
                             [](PySystem& s) { return vid::to_string(s.sys().config().estimator.force_frame); })
      .def_property_readonly("dynamics", [](PySystem& s) { return s.sys().dynamics(); })
      .def_property_readonly("estimates", [](PySystem& s) { return s.sys().estimates(); })
      .def_property_readonly("camera_frames", [](PySystem& s) { return s.sys().camera_frames(); });

  m.def("run_dataset", &vid::python::run_dataset, py::arg("dataset"), py::arg("out_dir"), py::kw_only(),
        py::arg("config") = py::none(), py::arg("mode") = py::none(), py::arg("init") = py::none(),
        py::arg("features") = "auto", py::arg("start_s") = 0.0, py::arg("end_s") = py::none(),
        py::arg("strict") = false, py::arg("decode_threads") = 1, py::arg("progress") = false,
        "Run the estimator on a dataset folder exactly as vid_run does (same files in out_dir); "
        "returns summary.json as a dict.");
}
