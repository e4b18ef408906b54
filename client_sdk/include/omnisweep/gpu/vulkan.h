// Vulkan-Hpp as the SDK's compute runtime includes it: gpu/buffer.h, image.h, kernel.h,
// sequence.h and reproject/forward_warp.h, for code that records its own kernels (the server).
// The headers an app includes to receive and reproject frames (client/, reproject/reprojector.h,
// gpu/context.h) do not include it.
//
// Vulkan-Hpp's dispatchers carry debug-only members (vk::DispatchLoaderBase when NDEBUG is not
// defined), so an SDK built as Release and code built as Debug would disagree on the layout of
// every vk::raii object they share: a crash or worse. This header pins Vulkan-Hpp to its NDEBUG
// layout for every includer, then restores the includer's NDEBUG and assert(). Code that uses the
// runtime headers includes them before <vulkan/vulkan.hpp>, or builds with NDEBUG.
#pragma once

#if defined(VULKAN_HPP) && !defined(NDEBUG) && !defined(OMNISWEEP_VULKAN_PINNED)
#error \
    "<vulkan/vulkan.hpp> was included without NDEBUG before omnisweep's headers: include omnisweep first (see omnisweep/gpu/vulkan.h)"
#endif

#ifndef NDEBUG
#define NDEBUG
#include <vulkan/vulkan_raii.hpp>
#undef NDEBUG
#include <cassert>  // assert() as the includer had it
#else
#include <vulkan/vulkan_raii.hpp>
#endif

#define OMNISWEEP_VULKAN_PINNED 1
