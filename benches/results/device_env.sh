# Sourced by the device scripts: on the device machine (and never on a workstation), unpack
# the carried Vulkan loader packages into / and point the loader at NVIDIA's driver, as the
# device tool's README says.
if [ -d /usr/local/nvidia ]; then
  for f in .gl/*.deb; do dpkg -x "$f" /; done
  ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
  export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
fi

# The carried binaries (`.dev/bins.tar.xz`, stripped builds of the commit under test) go to
# /root/bins; scripts name /root/bins/solari (or SOLARI_BIN).
unpack_bins() { mkdir -p /root/bins && tar xJf .dev/bins.tar.xz -C /root/bins; }

# The glTF file of shared scene $1 (in the repository, so nothing else needs carrying).
scene_file() { ls crates/solari-testdata/scenes/"$1"/*.gltf | head -n 1; }
