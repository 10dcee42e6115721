// Keeps every Vulkan driver (ICD) and layer loaded in this process mapped until exit.
//
// The Vulkan loader dlcloses its ICDs at vkDestroyInstance. Mesa's lavapipe makes a
// one-time, process-lifetime allocation inside vkEnumeratePhysicalDevices; once the
// driver is unmapped, LeakSanitizer reports it at exit with bare addresses in an
// "<unknown module>", which no suppression by library (tests/sanitizers/lsan.supp)
// can match. A pinned driver keeps its name in those frames, so `leak:libvulkan_lvp.so`
// applies and our own leaks are still reported. The same holds for layers: the
// Khronos validation layer with synchronization validation on keeps allocations
// past vkDestroyInstance. The runtime pins whatever drivers and layers are loaded once
// it is handed the app's Vulkan objects (the GPU sample engine's adapter, and tests with
// their own instance, do the same);
// a driver is recognised by the export that the loader-ICD interface requires of
// every ICD (vk_icdGetInstanceProcAddr), a layer by the loader-layer interface's
// (vkNegotiateLoaderLayerInterfaceVersion), never by file name or path.
// Libraries with thread-local storage stay mapped too (pinned again at
// xrDestroyInstance, when the loaders are about to dlclose layers): LeakSanitizer
// walks every thread's dynamic TLS at exit, and an entry of an unloaded library
// points at unmapped memory and crashes its tracer.
#pragma once

#include <dlfcn.h>
#include <link.h>

#include <cstddef>
#include <string>
#include <vector>

namespace foveart::sim {

inline void pin_loaded_vulkan_icds_and_layers() {
  struct Loaded {
    std::vector<std::string> paths;
    std::vector<bool> has_tls;
  } loaded;
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* out) {
        if (info->dlpi_name != nullptr && info->dlpi_name[0] != '\0') {
          auto* l = static_cast<Loaded*>(out);
          bool tls = false;
          for (int i = 0; i < info->dlpi_phnum; ++i) tls = tls || (info->dlpi_phdr[i].p_type == PT_TLS && info->dlpi_phdr[i].p_memsz > 0);
          l->paths.emplace_back(info->dlpi_name);
          l->has_tls.push_back(tls);
        }
        return 0;
      },
      &loaded);
  for (std::size_t i = 0; i < loaded.paths.size(); ++i) {
    if (!loaded.has_tls[i]) continue;
    if (void* pinned = dlopen(loaded.paths[i].c_str(), RTLD_LAZY | RTLD_NOLOAD | RTLD_NODELETE)) dlclose(pinned);
  }
  const std::vector<std::string>& paths = loaded.paths;
  for (const std::string& path : paths) {
    void* handle = dlopen(path.c_str(), RTLD_LAZY | RTLD_NOLOAD);
    if (handle == nullptr) continue;
    // dlsym also searches the object's dependencies: the entry point must be its own.
    auto exports = [&](const char* symbol) {
      void* entry = dlsym(handle, symbol);
      Dl_info owner{};
      return entry != nullptr && dladdr(entry, &owner) != 0 && owner.dli_fname != nullptr && path == owner.dli_fname;
    };
    if (exports("vk_icdGetInstanceProcAddr") || exports("vkNegotiateLoaderLayerInterfaceVersion")) {
      // RTLD_NOLOAD | RTLD_NODELETE marks the already loaded object as never unloaded.
      if (void* pinned = dlopen(path.c_str(), RTLD_LAZY | RTLD_NOLOAD | RTLD_NODELETE)) {
        dlclose(pinned);
      }
    }
    dlclose(handle);
  }
}

}  // namespace foveart::sim
