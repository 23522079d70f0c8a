# cmake -DPYTHON=... -DSOURCE=clients/python -DWORK=dir -DSITE=dir -P install_package.cmake
# Installs the package from a copy of its source (pip builds in tree; the checkout stays clean)
# into SITE, replacing what an earlier run installed.
file(REMOVE_RECURSE ${WORK} ${SITE})
file(COPY ${SOURCE}/ DESTINATION ${WORK} PATTERN build EXCLUDE PATTERN "*.egg-info" EXCLUDE
     PATTERN __pycache__ EXCLUDE)
execute_process(COMMAND ${PYTHON} -m pip install --quiet --no-build-isolation --no-deps --target ${SITE} ${WORK}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pip install of the depath package failed (${rc})")
endif()
