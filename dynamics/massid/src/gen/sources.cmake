# Data generation of the mass-identification study (owner: mass-id data engineer).
# Included by dynamics/massid/CMakeLists.txt before vid_massid_core is created.
set(_gen ${CMAKE_CURRENT_LIST_DIR})
list(APPEND MASSID_GEN_SOURCES
  ${_gen}/run_csv.cpp
  ${_gen}/dataset_index.cpp
  ${_gen}/reference_trajectory.cpp
  ${_gen}/mass_profile.cpp
  ${_gen}/mpc_controller.cpp
  ${_gen}/run_simulator.cpp
  ${_gen}/study_config.cpp
  ${_gen}/dataset_generator.cpp)
