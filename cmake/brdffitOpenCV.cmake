# The OpenCV modules brdffit uses, in OpenCV_LIBS: OpenCV's own CMake package when it is
# installed (Debian: libopencv-dev, which pulls in every module, VTK, Qt, ...), else each module
# found on its own (Debian: libopencv-{core,imgproc,imgcodecs,videoio,photo}-dev, which
# scripts/install-deps.sh installs), as imported targets named as OpenCV's package names them
# (opencv_core, ...). Sets OpenCV_FOUND. Used by the build and by brdffitConfig.cmake.
set(BRDFFIT_OPENCV_MODULES core imgproc imgcodecs videoio photo)
find_package(OpenCV QUIET COMPONENTS ${BRDFFIT_OPENCV_MODULES})
if(NOT OpenCV_FOUND)
  find_path(BRDFFIT_OPENCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4)
  set(OpenCV_FOUND TRUE)
  set(OpenCV_LIBS)
  foreach(module ${BRDFFIT_OPENCV_MODULES})
    find_library(BRDFFIT_OPENCV_${module}_LIBRARY opencv_${module})
    if(NOT BRDFFIT_OPENCV_INCLUDE_DIR OR NOT BRDFFIT_OPENCV_${module}_LIBRARY)
      set(OpenCV_FOUND FALSE)
    elseif(NOT TARGET opencv_${module})
      add_library(opencv_${module} UNKNOWN IMPORTED)
      set_target_properties(opencv_${module} PROPERTIES IMPORTED_LOCATION ${BRDFFIT_OPENCV_${module}_LIBRARY}
                                                        INTERFACE_INCLUDE_DIRECTORIES ${BRDFFIT_OPENCV_INCLUDE_DIR})
    endif()
    list(APPEND OpenCV_LIBS opencv_${module})
  endforeach()
endif()
