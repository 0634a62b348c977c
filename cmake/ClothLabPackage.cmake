# Installs the plugin SDK as a CMake package: <prefix>/lib/cmake/ClothLab/ClothLabConfig.cmake
# (+ version file) exporting ClothLab::sdk and clothlab_add_plugin(). The SDK target and
# its headers are installed by core/CMakeLists.txt into the export set ClothLabTargets.
include(CMakePackageConfigHelpers)

set(CLOTHLAB_CMAKE_INSTALL_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/ClothLab")

# The ABI major a plugin built against this SDK carries, for find_package users.
file(STRINGS "${PROJECT_SOURCE_DIR}/core/include/clothlab/abi/version.h" _clothlab_abi_line
     REGEX "^#define CLOTHLAB_ABI_VERSION_MAJOR ")
string(REGEX MATCH "[0-9]+" CLOTHLAB_ABI_VERSION_MAJOR "${_clothlab_abi_line}")

install(EXPORT ClothLabTargets NAMESPACE ClothLab:: DESTINATION "${CLOTHLAB_CMAKE_INSTALL_DIR}")
configure_package_config_file("${CMAKE_CURRENT_LIST_DIR}/ClothLabConfig.cmake.in"
                              "${PROJECT_BINARY_DIR}/ClothLabConfig.cmake"
                              INSTALL_DESTINATION "${CLOTHLAB_CMAKE_INSTALL_DIR}")
write_basic_package_version_file("${PROJECT_BINARY_DIR}/ClothLabConfigVersion.cmake"
                                 VERSION "${PROJECT_VERSION}" COMPATIBILITY SameMajorVersion)
install(FILES "${PROJECT_BINARY_DIR}/ClothLabConfig.cmake"
              "${PROJECT_BINARY_DIR}/ClothLabConfigVersion.cmake"
              "${CMAKE_CURRENT_LIST_DIR}/ClothLabPlugin.cmake"
              "${CMAKE_CURRENT_LIST_DIR}/clothlab_plugin.map"
        DESTINATION "${CLOTHLAB_CMAKE_INSTALL_DIR}")
