// python/octray_module.hpp — what the module's two source files share.
#pragma once

#include <octray/packet_scene.hpp>
#include <octray/scene.hpp>

#include <pybind11/pybind11.h>

#include <memory>
#include <string>

namespace py = pybind11;
using namespace pybind11::literals;

namespace octray::python {

// octray.Scene's C++ side: the authoring scene (as loaded) and its compiled
// form, made once; immutable, so calls on one Scene may run concurrently.
struct SceneHandle {
    SceneHandle(Scene s, std::string src);
    std::shared_ptr<const Scene> scene;
    std::string source;  // the JSON file, or "" for a dict
    PacketScene compiled;
};

std::shared_ptr<SceneHandle> load(const std::string& path);

// A `threads` argument, checked as the CLI's --threads (0 .. 1024; 0 = every
// core); ValueError naming it otherwise. Returns it unresolved.
int checked_threads(int threads);

void bind_scene(py::module_& m, py::class_<SceneHandle, std::shared_ptr<SceneHandle>>& cls);
void bind_harness(py::module_& m, py::class_<SceneHandle, std::shared_ptr<SceneHandle>>& cls);

}  // namespace octray::python
