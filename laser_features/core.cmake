# The ROS-free core library of laser_features: plain CMake, include()d by the catkin CMakeLists.txt
# of the package (and by standalone test builds). Defines the target `laser_features_core`.
#
#   include(${CMAKE_CURRENT_LIST_DIR}/core.cmake)
#   target_link_libraries(laser_features_node laser_features_core ${catkin_LIBRARIES})

include_guard(GLOBAL)
set(LASER_FEATURES_CORE_DIR ${CMAKE_CURRENT_LIST_DIR})

find_package(Eigen3 REQUIRED)  # header-only

add_library(laser_features_core
  ${LASER_FEATURES_CORE_DIR}/src/geometry.cpp
  ${LASER_FEATURES_CORE_DIR}/src/chi_square.cpp
  ${LASER_FEATURES_CORE_DIR}/src/file_io.cpp
  ${LASER_FEATURES_CORE_DIR}/src/scan.cpp
  ${LASER_FEATURES_CORE_DIR}/src/line_extractor.cpp
  ${LASER_FEATURES_CORE_DIR}/src/line_extractor_split.cpp
  ${LASER_FEATURES_CORE_DIR}/src/line_extractor_merge.cpp
  ${LASER_FEATURES_CORE_DIR}/src/line_extractor_boundaries.cpp
  ${LASER_FEATURES_CORE_DIR}/src/line_fit.cpp
  ${LASER_FEATURES_CORE_DIR}/src/corner_extractor.cpp
  ${LASER_FEATURES_CORE_DIR}/src/place_classifier.cpp
  ${LASER_FEATURES_CORE_DIR}/src/opening_extractor.cpp
  ${LASER_FEATURES_CORE_DIR}/src/feature_extractor.cpp
  ${LASER_FEATURES_CORE_DIR}/src/odometry_consistency.cpp
  ${LASER_FEATURES_CORE_DIR}/src/building_axes.cpp
)
target_include_directories(laser_features_core PUBLIC
  $<BUILD_INTERFACE:${LASER_FEATURES_CORE_DIR}/include>
)
if(TARGET Eigen3::Eigen)
  target_link_libraries(laser_features_core PUBLIC Eigen3::Eigen)
else()
  target_include_directories(laser_features_core SYSTEM PUBLIC ${EIGEN3_INCLUDE_DIR})
endif()
target_compile_features(laser_features_core PUBLIC cxx_std_17)
set_target_properties(laser_features_core PROPERTIES POSITION_INDEPENDENT_CODE ON)
