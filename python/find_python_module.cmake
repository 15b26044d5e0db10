# Decides DYNAPATH_PYTHON: the Python module (python/) is built when a
# Python 3 interpreter with numpy, its headers and pybind11 are found
# (Debian: python3-dev python3-numpy pybind11-dev). Default ON when found;
# -DDYNAPATH_PYTHON=OFF skips it, ON without them is an error.
#
# The first `python3` on PATH may be another installation than the one the
# Debian packages went into (a pyenv shim, a virtualenv without numpy), so
# the interpreter is the first of PATH's python3 and /usr/bin/python3 that
# imports numpy, unless -DPython3_EXECUTABLE names one.
set(dynapath_python_missing "")
# Chosen in every build, the checked ones too: the tests run their python3
# with it (tests/CMakeLists.txt).
if(NOT Python3_EXECUTABLE)
  find_program(dynapath_path_python3 python3)
  foreach(candidate ${dynapath_path_python3} /usr/bin/python3)
    if(EXISTS "${candidate}")
      execute_process(COMMAND "${candidate}" -c "import numpy" RESULT_VARIABLE numpy_missing
                      OUTPUT_QUIET ERROR_QUIET)
      if(numpy_missing EQUAL 0)
        set(Python3_EXECUTABLE "${candidate}" CACHE FILEPATH "Python 3 interpreter")
        break()
      endif()
    endif()
  endforeach()
endif()
# A sanitized or fuzzer-instrumented extension cannot be loaded by an
# uninstrumented python3 (the sanitizer runtime must come first), so the
# checked builds (scripts/checked_builds.sh) leave the module out.
if(DYNAPATH_SANITIZE OR DYNAPATH_FUZZ)
  if(DYNAPATH_PYTHON)
    message(FATAL_ERROR "DYNAPATH_PYTHON cannot be combined with DYNAPATH_SANITIZE or DYNAPATH_FUZZ")
  endif()
  option(DYNAPATH_PYTHON "Build the Python module dynapath (python/)" OFF)
  message(STATUS "Python module skipped: not in a sanitized or fuzzing build")
  return()
endif()
find_package(Python3 COMPONENTS Interpreter Development.Module NumPy QUIET)
if(NOT Python3_Interpreter_FOUND)
  list(APPEND dynapath_python_missing "a python3 interpreter (python3)")
endif()
if(NOT Python3_Development.Module_FOUND)
  list(APPEND dynapath_python_missing "Python headers (python3-dev)")
endif()
if(NOT Python3_NumPy_FOUND)
  list(APPEND dynapath_python_missing "numpy (python3-numpy)")
endif()
if(NOT dynapath_python_missing)
  find_package(pybind11 CONFIG QUIET)
  if(NOT pybind11_FOUND)
    list(APPEND dynapath_python_missing "pybind11 (pybind11-dev)")
  endif()
endif()

if(dynapath_python_missing)
  string(REPLACE ";" ", " dynapath_python_missing_text "${dynapath_python_missing}")
  if(DYNAPATH_PYTHON)
    message(FATAL_ERROR "DYNAPATH_PYTHON is ON but ${dynapath_python_missing_text} "
                        "not found (scripts/install-deps.sh installs them)")
  endif()
  option(DYNAPATH_PYTHON "Build the Python module dynapath (python/)" OFF)
  message(STATUS "Python module skipped: ${dynapath_python_missing_text} not found "
                 "(scripts/install-deps.sh installs them)")
else()
  option(DYNAPATH_PYTHON "Build the Python module dynapath (python/)" ON)
  if(DYNAPATH_PYTHON)
    message(STATUS "Python module: ${Python3_EXECUTABLE}, numpy ${Python3_NumPy_VERSION}, "
                   "pybind11 ${pybind11_VERSION}")
  else()
    message(STATUS "Python module skipped (DYNAPATH_PYTHON=OFF)")
  endif()
endif()
