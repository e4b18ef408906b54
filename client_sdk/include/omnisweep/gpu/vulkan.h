// Vulkan-Hpp as every omnisweep header includes it. Its dispatchers carry debug-only members
// (vk::DispatchLoaderBase when NDEBUG is not defined), so an SDK built as Release and an app
// built as Debug would disagree on the layout of every vk::raii object they share: a crash or
// worse. This header pins Vulkan-Hpp to its NDEBUG layout for every includer, then restores
// the includer's NDEBUG and assert(). Include omnisweep headers before <vulkan/vulkan.hpp>, or
// build with NDEBUG.
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
