// octray/octray.hpp — the whole public API in one include.
//
//     #include <octray/octray.hpp>
//
// Scene authoring types (scene.hpp), the compiled SoA scene (packet_scene.hpp),
// ray/hit/colour packets (packet.hpp), the kernel table and its dispatch
// (kernels.hpp), precision modes, features, images and the
// scalar double reference renderer. docs/API.md explains how to use them.
// Whole images (render.hpp) need octray::render linked as well.
#pragma once

#include <octray/features.hpp>
#include <octray/image.hpp>
#include <octray/kernels.hpp>
#include <octray/packet.hpp>
#include <octray/packet_scene.hpp>
#include <octray/precision.hpp>
#include <octray/reference.hpp>
#include <octray/render.hpp>
#include <octray/scene.hpp>
#include <octray/threads.hpp>
#include <octray/vec3.hpp>
