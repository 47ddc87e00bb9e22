# Model-based mass-identification methods (EKF, UKF, MSCKF, SWLS) and the study runner;
# included by dynamics/massid/CMakeLists.txt.
set(MASSID_FILTER_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/quadrotor_mass_model.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tuning.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mass_change_detector.cpp
  ${CMAKE_CURRENT_LIST_DIR}/msckf.cpp
  ${CMAKE_CURRENT_LIST_DIR}/swls_residuals.cpp
  ${CMAKE_CURRENT_LIST_DIR}/swls.cpp
  ${CMAKE_CURRENT_LIST_DIR}/estimators.cpp
  ${CMAKE_CURRENT_LIST_DIR}/study_runner.cpp
  ${CMAKE_CURRENT_LIST_DIR}/study_io.cpp)
# The study runner offers the ELM family (train_data_driven) when src/elm/ is part of the build.
if(EXISTS ${CMAKE_CURRENT_LIST_DIR}/../elm/sources.cmake)
  set_source_files_properties(${CMAKE_CURRENT_LIST_DIR}/study_runner.cpp
    PROPERTIES COMPILE_DEFINITIONS VID_MASSID_HAVE_ELM=1)
endif()
