// The shared object as the loader sees it: one exported symbol, and a
// negotiation that checks every struct before trusting it.
#include <dlfcn.h>

#include <cstring>

#include <gtest/gtest.h>

#include "barrier.hpp"
#include "layer/XR_FOVEART_foveated_ray_tracing.h"
#include "loader_interfaces.h"
#include "loader_structs.hpp"

namespace foveart::layer {
namespace {

class Negotiation : public ::testing::Test {
 protected:
  void SetUp() override {
    handle_ = dlopen(FOVEART_LAYER_SO, RTLD_NOW | RTLD_LOCAL);
    ASSERT_NE(handle_, nullptr) << dlerror();
    negotiate_ = reinterpret_cast<PFN_xrNegotiateLoaderApiLayerInterface>(
        dlsym(handle_, "xrNegotiateLoaderApiLayerInterface"));
    ASSERT_NE(negotiate_, nullptr);
    loader_info_ = test::conforming_loader_info();
    request_ = test::empty_api_layer_request();
  }
  void TearDown() override {
    if (handle_ != nullptr) dlclose(handle_);
  }

  void* handle_ = nullptr;
  PFN_xrNegotiateLoaderApiLayerInterface negotiate_ = nullptr;
  XrNegotiateLoaderInfo loader_info_{};
  XrNegotiateApiLayerRequest request_{};
};

TEST_F(Negotiation, OnlyTheNegotiationSymbolIsExported) {
  for (const char* hidden : {"xrGetInstanceProcAddr", "xrCreateApiLayerInstance", "xrEndFrame",
                             "_ZN7foveart5layer9negotiateEPK21XrNegotiateLoaderInfoPKcP26XrNegotiateApiLayerRequest"}) {
    EXPECT_EQ(dlsym(handle_, hidden), nullptr) << hidden;
  }
}

TEST_F(Negotiation, AcceptsTheLoaderAndFillsTheRequest) {
  ASSERT_EQ(negotiate_(&loader_info_, XR_FOVEART_API_LAYER_NAME, &request_), XR_SUCCESS);
  EXPECT_EQ(request_.layerInterfaceVersion, 1u);
  EXPECT_NE(request_.getInstanceProcAddr, nullptr);
  EXPECT_NE(request_.createApiLayerInstance, nullptr);
}

TEST_F(Negotiation, RejectsAnotherLayersName) {
  EXPECT_EQ(negotiate_(&loader_info_, "XR_APILAYER_someone_else", &request_), XR_ERROR_INITIALIZATION_FAILED);
  EXPECT_EQ(negotiate_(&loader_info_, nullptr, &request_), XR_ERROR_INITIALIZATION_FAILED);
  EXPECT_EQ(request_.getInstanceProcAddr, nullptr);
}

TEST_F(Negotiation, RejectsMalformedStructs) {
  XrNegotiateLoaderInfo bad_info = loader_info_;
  bad_info.structSize = sizeof(bad_info) - 8;
  EXPECT_EQ(negotiate_(&bad_info, XR_FOVEART_API_LAYER_NAME, &request_), XR_ERROR_INITIALIZATION_FAILED);
  XrNegotiateApiLayerRequest bad_request = request_;
  bad_request.structType = XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST;
  EXPECT_EQ(negotiate_(&loader_info_, XR_FOVEART_API_LAYER_NAME, &bad_request), XR_ERROR_INITIALIZATION_FAILED);
  EXPECT_EQ(negotiate_(nullptr, XR_FOVEART_API_LAYER_NAME, &request_), XR_ERROR_INITIALIZATION_FAILED);
}

TEST_F(Negotiation, RejectsALoaderWithoutInterfaceVersionOne) {
  loader_info_.minInterfaceVersion = 2;
  loader_info_.maxInterfaceVersion = 3;
  EXPECT_EQ(negotiate_(&loader_info_, XR_FOVEART_API_LAYER_NAME, &request_), XR_ERROR_INITIALIZATION_FAILED);
}

TEST_F(Negotiation, GetInstanceProcAddrRefusesUnknownInstances) {
  ASSERT_EQ(negotiate_(&loader_info_, XR_FOVEART_API_LAYER_NAME, &request_), XR_SUCCESS);
  PFN_xrVoidFunction fn = nullptr;
  EXPECT_EQ(request_.getInstanceProcAddr(reinterpret_cast<XrInstance>(0x1234), "xrEndFrame", &fn),
            XR_ERROR_HANDLE_INVALID);
  EXPECT_EQ(fn, nullptr);
  EXPECT_EQ(request_.getInstanceProcAddr(XR_NULL_HANDLE, "xrGetInstanceProcAddr", &fn), XR_SUCCESS);
  EXPECT_NE(fn, nullptr);
}

TEST_F(Negotiation, CreateRejectsAChainNotMeantForThisLayer) {
  ASSERT_EQ(negotiate_(&loader_info_, XR_FOVEART_API_LAYER_NAME, &request_), XR_SUCCESS);
  XrApiLayerNextInfo next{};
  next.structType = XR_LOADER_INTERFACE_STRUCT_API_LAYER_NEXT_INFO;
  next.structVersion = FOVEART_API_LAYER_NEXT_INFO_STRUCT_VERSION;
  next.structSize = sizeof(next);
  std::strcpy(next.layerName, "XR_APILAYER_someone_else");
  XrApiLayerCreateInfo layer_info{};
  layer_info.structType = XR_LOADER_INTERFACE_STRUCT_API_LAYER_CREATE_INFO;
  layer_info.structVersion = FOVEART_API_LAYER_CREATE_INFO_STRUCT_VERSION;
  layer_info.structSize = sizeof(layer_info);
  layer_info.nextInfo = &next;
  XrInstanceCreateInfo create{};
  create.type = XR_TYPE_INSTANCE_CREATE_INFO;
  XrInstance instance = XR_NULL_HANDLE;
  EXPECT_EQ(request_.createApiLayerInstance(&create, &layer_info, &instance), XR_ERROR_INITIALIZATION_FAILED);
  EXPECT_EQ(instance, XR_NULL_HANDLE);
}

TEST(ExceptionBarrier, ThrowBecomesRuntimeFailure) {
  EXPECT_EQ(exception_barrier("test", []() -> XrResult { throw std::runtime_error("boom"); }),
            XR_ERROR_RUNTIME_FAILURE);
  EXPECT_EQ(exception_barrier("test", []() -> XrResult { throw 42; }), XR_ERROR_RUNTIME_FAILURE);
  EXPECT_EQ(exception_barrier("test", []() -> XrResult { return XR_TIMEOUT_EXPIRED; }), XR_TIMEOUT_EXPIRED);
}

}  // namespace
}  // namespace foveart::layer
