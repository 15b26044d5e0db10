# Included by tools/CMakeLists.txt at configure time: defines
# DYNAPATH_GIT_COMMIT (`git describe --always --dirty` of the source tree, or
# "unknown" without git) and makes CMake re-run configure when the checked-out
# commit or the index changes, so the id is neither asked at run time nor
# refreshed by a command at every build. (Edits not yet added to the index do
# not trigger it: such a build may say "abc1234" where "abc1234-dirty" would
# be exact.)
find_package(Git QUIET)
set(DYNAPATH_GIT_COMMIT "unknown")
if(GIT_FOUND)
  execute_process(COMMAND ${GIT_EXECUTABLE} -C ${PROJECT_SOURCE_DIR} describe --always --dirty
                  OUTPUT_VARIABLE described OUTPUT_STRIP_TRAILING_WHITESPACE
                  RESULT_VARIABLE result ERROR_QUIET)
  if(result EQUAL 0 AND described)
    set(DYNAPATH_GIT_COMMIT "${described}")
  endif()
  execute_process(COMMAND ${GIT_EXECUTABLE} -C ${PROJECT_SOURCE_DIR} rev-parse --absolute-git-dir
                  OUTPUT_VARIABLE git_dir OUTPUT_STRIP_TRAILING_WHITESPACE
                  RESULT_VARIABLE result ERROR_QUIET)
  if(result EQUAL 0)
    foreach(file HEAD index)
      if(EXISTS "${git_dir}/${file}")
        set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
                     "${git_dir}/${file}")
      endif()
    endforeach()
  endif()
endif()
