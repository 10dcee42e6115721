#include "state.hpp"

namespace foveart::layer {
namespace {

uint64_t key(XrFoveatedRendererFOVEART handle) { return reinterpret_cast<uintptr_t>(handle); }

}  // namespace

Registry& Registry::get() {
  static Registry registry;  // emptied by xrDestroyInstance; destroyed at unload
  return registry;
}

void Registry::add_instance(std::shared_ptr<InstanceState> state) {
  std::lock_guard lock(mutex_);
  instances_[state->handle] = std::move(state);
}

std::shared_ptr<InstanceState> Registry::instance(XrInstance handle) const {
  std::lock_guard lock(mutex_);
  auto it = instances_.find(handle);
  return it == instances_.end() ? nullptr : it->second;
}

std::vector<std::shared_ptr<FoveatedRenderer>> Registry::remove_instance(XrInstance handle) {
  std::vector<std::shared_ptr<FoveatedRenderer>> removed;
  std::lock_guard lock(mutex_);
  for (auto it = sessions_.begin(); it != sessions_.end();) {
    if (it->second->instance->handle != handle) {
      ++it;
      continue;
    }
    erase_children_of_session(it->first, &removed);
    it = sessions_.erase(it);
  }
  std::erase_if(vulkan_devices_, [&](const auto& entry) { return entry.second.instance == handle; });
  std::erase_if(vulkan_instances_, [&](const auto& entry) { return entry.second.instance == handle; });
  instances_.erase(handle);
  return removed;
}

void Registry::add_session(std::shared_ptr<SessionState> state) {
  std::lock_guard lock(mutex_);
  sessions_[state->handle] = std::move(state);
}

std::shared_ptr<SessionState> Registry::session(XrSession handle) const {
  std::lock_guard lock(mutex_);
  auto it = sessions_.find(handle);
  return it == sessions_.end() ? nullptr : it->second;
}

std::vector<std::shared_ptr<FoveatedRenderer>> Registry::remove_session(XrSession handle) {
  std::vector<std::shared_ptr<FoveatedRenderer>> removed;
  std::lock_guard lock(mutex_);
  erase_children_of_session(handle, &removed);
  sessions_.erase(handle);
  return removed;
}

void Registry::erase_children_of_session(XrSession session, std::vector<std::shared_ptr<FoveatedRenderer>>* removed) {
  for (auto r = renderers_.begin(); r != renderers_.end();) {
    if (r->second.session == session) {
      removed->push_back(std::move(r->second.renderer));
      r = renderers_.erase(r);
    } else {
      ++r;
    }
  }
  std::erase_if(swapchains_, [&](const auto& entry) { return entry.second.session == session; });
}

XrFoveatedRendererFOVEART Registry::add_renderer(XrSession session, std::shared_ptr<FoveatedRenderer> renderer) {
  std::lock_guard lock(mutex_);
  // Handles are opaque ids, never pointers: a stale handle finds nothing.
  const uint64_t id = next_renderer_id_++;
  renderers_[id] = RendererEntry{session, std::move(renderer)};
  return reinterpret_cast<XrFoveatedRendererFOVEART>(static_cast<uintptr_t>(id));
}

std::shared_ptr<FoveatedRenderer> Registry::renderer(XrFoveatedRendererFOVEART handle) const {
  std::lock_guard lock(mutex_);
  auto it = renderers_.find(key(handle));
  return it == renderers_.end() ? nullptr : it->second.renderer;
}

std::shared_ptr<FoveatedRenderer> Registry::renderer_of_session(XrFoveatedRendererFOVEART handle, XrSession session,
                                                                std::shared_ptr<FoveatedRenderer>* out_other) const {
  std::lock_guard lock(mutex_);
  out_other->reset();
  auto it = renderers_.find(key(handle));
  if (it == renderers_.end()) return nullptr;
  if (it->second.session != session) {
    *out_other = it->second.renderer;
    return nullptr;
  }
  return it->second.renderer;
}

std::shared_ptr<FoveatedRenderer> Registry::remove_renderer(XrFoveatedRendererFOVEART handle) {
  std::lock_guard lock(mutex_);
  auto it = renderers_.find(key(handle));
  if (it == renderers_.end()) return nullptr;
  auto renderer = std::move(it->second.renderer);
  renderers_.erase(it);
  return renderer;
}

bool Registry::session_has_renderers(XrSession session) const {
  std::lock_guard lock(mutex_);
  for (const auto& [id, entry] : renderers_) {
    if (entry.session == session) return true;
  }
  return false;
}

void Registry::add_swapchain(XrSwapchain handle, const SwapchainExtent& extent) {
  std::lock_guard lock(mutex_);
  swapchains_[handle] = extent;
}

void Registry::remove_swapchain(XrSwapchain handle) {
  std::lock_guard lock(mutex_);
  swapchains_.erase(handle);
}

PFN_xrDestroySwapchain Registry::destroy_swapchain_function(XrSwapchain handle) const {
  std::lock_guard lock(mutex_);
  auto it = swapchains_.find(handle);
  if (it == swapchains_.end()) return nullptr;
  auto session = sessions_.find(it->second.session);
  return session == sessions_.end() ? nullptr : session->second->instance->next.DestroySwapchain;
}

std::optional<SwapchainExtent> Registry::swapchain(XrSwapchain handle, XrSession session) const {
  std::lock_guard lock(mutex_);
  auto it = swapchains_.find(handle);
  if (it == swapchains_.end() || it->second.session != session) return std::nullopt;
  return it->second;
}

void Registry::add_vulkan_device(XrInstance instance, VkDevice device, const VulkanDeviceFeatures& features) {
  std::lock_guard lock(mutex_);
  vulkan_devices_[device] = VulkanDeviceEntry{instance, features};
}

void Registry::add_vulkan_instance(XrInstance instance, VkInstance vulkan_instance, uint32_t api_version) {
  std::lock_guard lock(mutex_);
  vulkan_instances_[vulkan_instance] = VulkanInstanceEntry{instance, api_version};
}

uint32_t Registry::vulkan_instance_api_version(VkInstance vulkan_instance) const {
  std::lock_guard lock(mutex_);
  auto it = vulkan_instances_.find(vulkan_instance);
  return it == vulkan_instances_.end() ? 0 : it->second.api_version;
}

VulkanDeviceFeatures Registry::vulkan_device(VkDevice device) const {
  std::lock_guard lock(mutex_);
  auto it = vulkan_devices_.find(device);
  return it == vulkan_devices_.end() ? VulkanDeviceFeatures{} : it->second.features;
}

std::size_t Registry::instance_count() const {
  std::lock_guard lock(mutex_);
  return instances_.size();
}

}  // namespace foveart::layer
