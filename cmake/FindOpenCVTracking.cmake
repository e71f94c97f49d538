# FindOpenCVTracking: the parts of OpenCV the AR renderer's camera tracking uses on top of
# OpenCVVideo (core, imgproc, videoio): features2d (ORB, matching), calib3d (chessboard
# calibration, homography, PnP) and video (pyramidal KLT), imgcodecs (reference images). Debian's split packages
# libopencv-features2d-dev, libopencv-calib3d-dev and libopencv-video-dev ship no
# OpenCVConfig.cmake, so the libraries are found directly. flann comes with features2d.
#
# Defines OpenCVTracking_FOUND and the imported target OpenCVTracking::OpenCVTracking
# (which links OpenCVVideo::OpenCVVideo too).
find_package(OpenCVVideo)
find_path(OpenCVTracking_INCLUDE_DIR opencv2/features2d.hpp PATH_SUFFIXES opencv4)
find_path(OpenCVTracking_calib3d_INCLUDE_DIR opencv2/calib3d.hpp PATH_SUFFIXES opencv4)
find_path(OpenCVTracking_video_INCLUDE_DIR opencv2/video/tracking.hpp PATH_SUFFIXES opencv4)
find_library(OpenCVTracking_features2d_LIBRARY opencv_features2d)
find_library(OpenCVTracking_calib3d_LIBRARY opencv_calib3d)
find_library(OpenCVTracking_video_LIBRARY opencv_video)
find_library(OpenCVTracking_flann_LIBRARY opencv_flann)
find_library(OpenCVTracking_imgcodecs_LIBRARY opencv_imgcodecs)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenCVTracking REQUIRED_VARS
  OpenCVVideo_FOUND OpenCVTracking_INCLUDE_DIR OpenCVTracking_calib3d_INCLUDE_DIR OpenCVTracking_video_INCLUDE_DIR
  OpenCVTracking_features2d_LIBRARY OpenCVTracking_calib3d_LIBRARY OpenCVTracking_video_LIBRARY
  OpenCVTracking_flann_LIBRARY OpenCVTracking_imgcodecs_LIBRARY)
mark_as_advanced(OpenCVTracking_INCLUDE_DIR OpenCVTracking_calib3d_INCLUDE_DIR OpenCVTracking_video_INCLUDE_DIR
                 OpenCVTracking_features2d_LIBRARY OpenCVTracking_calib3d_LIBRARY OpenCVTracking_video_LIBRARY
                 OpenCVTracking_flann_LIBRARY OpenCVTracking_imgcodecs_LIBRARY)

if(OpenCVTracking_FOUND AND NOT TARGET OpenCVTracking::OpenCVTracking)
  add_library(OpenCVTracking::OpenCVTracking INTERFACE IMPORTED)
  set_target_properties(OpenCVTracking::OpenCVTracking PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${OpenCVTracking_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES
      "${OpenCVTracking_calib3d_LIBRARY};${OpenCVTracking_features2d_LIBRARY};${OpenCVTracking_video_LIBRARY};${OpenCVTracking_flann_LIBRARY};${OpenCVTracking_imgcodecs_LIBRARY};OpenCVVideo::OpenCVVideo")
endif()
