# The ROS-free core library of ekf_local_map: plain CMake, include()d by the catkin CMakeLists.txt of
# the package (and by standalone test builds). Defines the target `ekf_local_map_core`; the including
# CMakeLists must provide `laser_features_core` first (include laser_features/core.cmake).
#
#   include(${CMAKE_CURRENT_LIST_DIR}/core.cmake)
#   target_link_libraries(ekf_local_map_node ekf_local_map_core ${catkin_LIBRARIES})

set(EKF_LOCAL_MAP_CORE_DIR ${CMAKE_CURRENT_LIST_DIR})

find_package(Eigen3 REQUIRED)  # header-only

add_library(ekf_local_map_core
  ${EKF_LOCAL_MAP_CORE_DIR}/src/measurement_model.cpp
  ${EKF_LOCAL_MAP_CORE_DIR}/src/odometry_noise.cpp
  ${EKF_LOCAL_MAP_CORE_DIR}/src/stochastic_map.cpp
  ${EKF_LOCAL_MAP_CORE_DIR}/src/stochastic_map_association.cpp
  ${EKF_LOCAL_MAP_CORE_DIR}/src/stochastic_map_fusion.cpp
  ${EKF_LOCAL_MAP_CORE_DIR}/src/update_kernels.cpp
  ${EKF_LOCAL_MAP_CORE_DIR}/src/place_maps.cpp
  ${EKF_LOCAL_MAP_CORE_DIR}/src/persistence.cpp
  ${EKF_LOCAL_MAP_CORE_DIR}/src/persistence_encode.cpp
)
target_include_directories(ekf_local_map_core PUBLIC
  $<BUILD_INTERFACE:${EKF_LOCAL_MAP_CORE_DIR}/include>
)
target_link_libraries(ekf_local_map_core PUBLIC laser_features_core)
if(TARGET Eigen3::Eigen)
  target_link_libraries(ekf_local_map_core PUBLIC Eigen3::Eigen)
else()
  target_include_directories(ekf_local_map_core SYSTEM PUBLIC ${EIGEN3_INCLUDE_DIR})
endif()
target_compile_features(ekf_local_map_core PUBLIC cxx_std_17)
set_target_properties(ekf_local_map_core PROPERTIES POSITION_INDEPENDENT_CODE ON)
