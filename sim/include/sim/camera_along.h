#pragma once
/// @file camera_along.h
/// @brief vid_sim --camera-along: the camera streams of a scenario (rendered images and/or
/// feat0 + landmarks.csv, same writer code as a normal run, docs/formats.md §1) along a
/// recorded trajectory instead of a simulated flight, for real recordings without a camera
/// (config/sim/README.md "Cameras along a recorded trajectory").
///
/// Only the scenario's cameras (calibration, rate), scene, render and features sections (and
/// seed, noise) are used; its trajectory, vehicle, IMU, rotor sensor, forces and ground truth are
/// ignored. Nothing but the camera streams is written: other files in DIR/mav0 (IMU, rotors,
/// ground truth of the real recording) are left as they are.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include "sim/pose_track.h"
#include "sim/scenario.h"

namespace vid::sim {

/// @brief Camera stamps of a track: start + round(k 1e9 / rate_hz) ns for k = 0, 1, ... up to
/// the track's last pose (the simulator's camera schedule, started at the first pose).
std::vector<TimeNs> camera_times_along(const PoseTrack& track, double rate_hz);

/// @brief What write_camera_along writes under root: mav0/camN (for the scenario's cameras),
/// mav0/feat0 and mav0/landmarks.csv.
std::vector<std::filesystem::path> camera_stream_paths(const Scenario& scenario, const std::filesystem::path& root);

/// @brief Write the scenario's camera streams along @p track into root/mav0 (landmarks in the
/// track's world W). Refuses (std::runtime_error naming the paths) if any of
/// camera_stream_paths exists, unless @p overwrite, which deletes exactly those first. Throws
/// io::ConfigError if the scenario has no camera output or a camera clock offset (not modelled
/// along a recording). progress(done, total) is called per frame. Returns the frames written.
std::uint64_t write_camera_along(const Scenario& scenario, const PoseTrack& track, const std::filesystem::path& root,
                                 bool overwrite, const std::function<void(std::uint64_t, std::uint64_t)>& progress = {});

}  // namespace vid::sim
