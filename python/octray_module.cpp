// python/octray_module.cpp — the Python module's core (docs/python.md): Scene
// (from a JSON file or a dict, geometry-only or not), whole images, the tone
// map, the camera's rays, the argument checks the other files share. The
// caller's rays (intersect, occluded, shade) are in ray_cast.cpp, their hit
// records in hit_record.cpp; the harnesses (verify, errtime, stability) and
// info() in octray_harness.cpp.
//
// Every C++ exception stops at this boundary: octray::SceneError and
// octray::InvalidScene become octray.SceneError (a ValueError) with the CLI's
// one-line message; pybind11 turns the rest into ValueError (invalid_argument),
// MemoryError (bad_alloc) or RuntimeError.
#include "octray_module.hpp"

#include "image_io.hpp"

#include <octray/reference.hpp>
#include <octray/render.hpp>
#include <octray/threads.hpp>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

namespace octray::python {

namespace {

std::string shape_str(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t k = 0; k < a.ndim(); ++k) s += (k ? ", " : "") + std::to_string(a.shape(k));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

// An array that owns a std::vector (no copy).
template <class T>
py::array_t<T> owning_array(std::vector<T>&& v, std::vector<py::ssize_t> shape) {
    auto* heap = new std::vector<T>(std::move(v));
    py::capsule owner(heap, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    return py::array_t<T>(shape, heap->data(), owner);
}

}  // namespace

// ---- arguments -----------------------------------------------------------------

int checked_threads(int threads) {
    if (threads < 0 || threads > 1024)
        throw py::value_error("threads: must be in [0, 1024] (0 = every core), got " + std::to_string(threads));
    return threads;
}

Path packet_path(const std::string& path) {
    if (path == "simd") return Path::simd;
    if (path == "scalar") return Path::scalar;
    throw py::value_error("path: expected 'simd' or 'scalar', got '" + path + "'");
}

Precision precision_mode(const std::string& mode) {
    std::string names;
    for (const Precision p : kPrecisions) {
        if (mode == precision_name(p)) {
            if (!precision_supported(p))
                throw py::value_error("mode: '" + mode + "' needs AVX-512 F+VL, which this CPU lacks");
            return p;
        }
        names += std::string(names.empty() ? "" : ", ") + precision_name(p);
    }
    throw py::value_error("mode: expected one of " + names + ", got '" + mode + "'");
}

Kernel kernel_for(const SceneHandle& s, const std::string& path, const std::string& mode) {
    const Path p = packet_path(path);
    const Precision precision = precision_mode(mode);
    const Kernel k = select_kernel(s.compiled, p, precision);
    // select_kernel falls back rather than fail; a caller who named a mode gets that mode or an error.
    if (k.precision != precision)
        throw py::value_error("mode: '" + mode + "' is not built for the " + path + " path here (it would run as '" +
                              precision_name(k.precision) + "')");
    return k;
}

// ---- Scene -------------------------------------------------------------------

SceneHandle::SceneHandle(Scene s, SceneSources src, std::string source_name)
    : scene(std::make_shared<const Scene>(std::move(s))), source(std::move(source_name)), sources(std::move(src)) {
    primitives = PrimitiveMap(*scene, sources);
    compiled = compile(*scene);
}

void SceneHandle::require(const char* call, bool camera, bool materials) const {
    const bool no_camera = camera && !has_camera(), no_materials = materials && !has_materials();
    if (!no_camera && !no_materials) return;
    const std::string what = no_camera && no_materials ? "no camera and no materials"
                             : no_camera               ? "no camera"
                                                       : "no materials";
    const std::string give = no_camera && no_materials ? "a \"camera\" and \"materials\""
                             : no_camera               ? "a \"camera\""
                                                       : "\"materials\"";
    throw py::value_error(std::string(call) + ": this scene has " + what +
                          " (a geometry-only scene: intersect and occluded only); give its dict " + give +
                          (no_materials ? ", and each object a \"material\"" : ""));
}

std::shared_ptr<SceneHandle> load(const std::string& path) {
    py::gil_scoped_release release;
    SceneSources sources;
    Scene scene = load_scene(path, &sources);
    return std::make_shared<SceneHandle>(std::move(scene), std::move(sources), path);
}

namespace {

std::shared_ptr<SceneHandle> from_json(const std::string& text, const std::string& base_dir, const py::dict& arrays) {
    std::map<std::size_t, MeshArrays> meshes;
    for (auto item : arrays) {
        const std::size_t index = item.first.cast<std::size_t>();
        const py::tuple vi = item.second.cast<py::tuple>();
        MeshArrays& m = meshes[index];
        if (!vi[0].is_none()) {
            const auto v = vi[0].cast<py::array_t<double, py::array::c_style>>();
            m.vertices.resize(std::size_t(v.shape(0)));
            std::copy_n(v.data(), 3 * m.vertices.size(), &m.vertices.data()->x);
        }
        if (!vi[1].is_none()) {
            const auto ix = vi[1].cast<py::array_t<std::uint32_t, py::array::c_style>>();
            m.indices.assign(ix.data(), ix.data() + ix.size());
        }
    }
    static_assert(sizeof(Vec3d) == 3 * sizeof(double), "Vec3d is three doubles");
    py::gil_scoped_release release;
    SceneSources sources;
    ParseOptions options;
    options.geometry_only = true;  // a dict may leave out the camera and the materials
    options.sources = &sources;
    Scene scene = parse_scene(text, "", base_dir, meshes, options);
    return std::make_shared<SceneHandle>(std::move(scene), std::move(sources), "");
}

// The camera's rays, pixel by pixel, rows top first: the camera kernel's floats.
py::tuple camera_rays(const SceneHandle& s) {
    s.require("camera_rays", true, false);
    const int w = s.compiled.width(), h = s.compiled.height();
    const Kernel k = select_kernel(s.compiled, Path::simd);
    std::vector<float> o(std::size_t(w) * std::size_t(h) * 3), d(o.size());
    {
        py::gil_scoped_release release;
        RayPacket8 rp;
        for (int y = 0; y < h; ++y)
            for (int x0 = 0; x0 < w; x0 += 8) {
                k.camera(s.compiled, x0, y, rp);
                for (int i = 0; i < 8 && x0 + i < w; ++i) {
                    const std::size_t px = 3 * (std::size_t(y) * std::size_t(w) + std::size_t(x0 + i));
                    o[px] = rp.ox[i], o[px + 1] = rp.oy[i], o[px + 2] = rp.oz[i];
                    d[px] = rp.dx[i], d[px + 1] = rp.dy[i], d[px + 2] = rp.dz[i];
                }
            }
    }
    return py::make_tuple(owning_array(std::move(o), {h, w, 3}), owning_array(std::move(d), {h, w, 3}));
}

// `octray render --hdr` (tools/cmd_render.cpp), step for step; `mode` as
// errtime's precision modes (the CLI's render runs exact).
py::array_t<float> render(const SceneHandle& s, const std::string& path, const py::object& width_obj, int threads,
                          const std::string& mode) {
    s.require("render", true, true);
    const bool reference = path == "reference";
    const Precision precision = precision_mode(mode);
    if (reference && precision != Precision::exact)
        throw py::value_error("mode: the reference path renders in double alone; mode is for 'simd' and 'scalar'");
    if (!reference) kernel_for(s, path, mode);  // the path and mode checked before the work
    int width = 0;
    if (!width_obj.is_none()) {
        width = width_obj.cast<int>();
        if (width < 1 || width > kMaxImageSide)
            throw py::value_error("width: must be in [1, " + std::to_string(kMaxImageSide) + "], got " +
                                  std::to_string(width));
    }
    const int nt = resolve_threads(checked_threads(threads));
    int w = 0, h = 0;
    std::vector<float> rgb;
    {
    py::gil_scoped_release release;
    const Scene* scene = s.scene.get();
    Scene resized;
    if (width > 0) {
        resized = *s.scene;
        const double aspect = double(resized.camera.height) / resized.camera.width;
        resized.camera.height = std::max(1, int(std::lround(width * aspect)));
        resized.camera.width = width;
        validate(resized);  // the image-size limits
        scene = &resized;
    }
    w = scene->camera.width, h = scene->camera.height;
    if (reference) {
        const Image<double> hdr = reference::render(*scene);
        rgb.resize(hdr.rgb.size());
        for (std::size_t k = 0; k < rgb.size(); ++k) rgb[k] = static_cast<float>(hdr.rgb[k]);  // as write_pfm stores it
    } else {
        CompileOptions options;
        options.threads = nt;
        const PacketScene rebuilt = width > 0 ? compile(*scene, options) : PacketScene();
        const PacketScene& packet = width > 0 ? rebuilt : s.compiled;
        const Kernel kernel = select_kernel(packet, packet_path(path), precision);
        Image<float> shown(w, h);
        PacketRender out = render_packet(kernel, packet, nt, {}, &shown);
        rgb = std::move(out.radiance.rgb);
    }
    }
    return owning_array(std::move(rgb), {h, w, 3});
}

py::array_t<std::uint8_t> tonemap(const SceneHandle& s, const py::handle& hdr_obj, const std::string& path) {
    py::module_ np = py::module_::import("numpy");
    py::array a = py::isinstance<py::array>(hdr_obj) ? py::reinterpret_borrow<py::array>(hdr_obj)
                                                     : py::array(np.attr("asarray")(hdr_obj, "dtype"_a = "float32"));
    if (a.dtype().kind() != 'f')
        throw py::type_error("hdr: expected a floating-point array, got dtype " + std::string(py::str(a.dtype())));
    if (a.ndim() < 1 || a.shape(a.ndim() - 1) != 3)
        throw py::value_error("hdr: expected an (H, W, 3) array, got shape " + shape_str(a));
    const auto f = np.attr("ascontiguousarray")(a, "dtype"_a = "float32").cast<py::array_t<float, py::array::c_style>>();
    const Kernel k = select_kernel(s.compiled, packet_path(path));
    const std::size_t pixels = std::size_t(f.size()) / 3;
    std::vector<py::ssize_t> shape(f.shape(), f.shape() + f.ndim());
    std::vector<std::uint8_t> out(pixels * 3);
    {
        const float* src = f.data();
        py::gil_scoped_release release;
        // Up to 2^20 pixels at a time as one row of the display image,
        // quantized as quantize() does.
        const std::size_t chunk = std::min<std::size_t>(pixels, 1u << 20);
        std::vector<ColorPacket8> in((chunk + 7) / 8), disp(in.size());
        for (std::size_t first = 0; first < pixels; first += chunk) {
            const std::size_t count = std::min(chunk, pixels - first);
            const std::size_t packets = (count + 7) / 8;
            in[packets - 1] = ColorPacket8{};  // lanes past the end: zero
            for (std::size_t i = 0; i < count; ++i) {
                const float* c = src + 3 * (first + i);
                in[i / 8].r[i % 8] = c[0], in[i / 8].g[i % 8] = c[1], in[i / 8].b[i % 8] = c[2];
            }
            k.tonemap_group(s.compiled, in.data(), disp.data(), int(packets));
            Image<float> row(int(count), 1);
            for (std::size_t i = 0; i < count; ++i) {
                float* c = row.pixel(int(i), 0);
                c[0] = disp[i / 8].r[i % 8], c[1] = disp[i / 8].g[i % 8], c[2] = disp[i / 8].b[i % 8];
            }
            const ImageRGB8 q = quantize(row);
            std::copy(q.rgb.begin(), q.rgb.end(), out.begin() + std::ptrdiff_t(3 * first));
        }
    }
    return owning_array(std::move(out), shape);
}

}  // namespace

void bind_scene(py::module_& m, py::class_<SceneHandle, std::shared_ptr<SceneHandle>>& cls) {
    m.def("_load", &load, "path"_a);
    m.def("_from_json", &from_json, "text"_a, "base_dir"_a, "arrays"_a);
    cls.def("camera_rays", &camera_rays);
    cls.def("render", &render, "path"_a = "simd", "width"_a = py::none(), "threads"_a = 0, py::kw_only(),
            "mode"_a = "exact");
    cls.def("tonemap", &tonemap, "hdr"_a, "path"_a = "simd");
    // A geometry-only scene has no camera, so no image size: None.
    auto side = [](const SceneHandle& s, int v) { return s.has_camera() ? py::object(py::int_(v)) : py::object(py::none()); };
    cls.def_property_readonly("width", [side](const SceneHandle& s) { return side(s, s.compiled.width()); });
    cls.def_property_readonly("height", [side](const SceneHandle& s) { return side(s, s.compiled.height()); });
    cls.def_property_readonly("has_camera", &SceneHandle::has_camera);
    cls.def_property_readonly("has_materials", &SceneHandle::has_materials);
    cls.def_property_readonly("primitive_count", [](const SceneHandle& s) { return s.compiled.primitive_count(); });
    cls.def_property_readonly("source", [](const SceneHandle& s) { return s.source; });
}

}  // namespace octray::python

PYBIND11_MODULE(_octray, m) {
    using namespace octray::python;
    m.doc() = "octray's packet kernels for numpy arrays (the compiled part of the octray package)";
    static py::exception<octray::SceneError> scene_error(m, "SceneError", PyExc_ValueError);
    py::register_exception_translator([](std::exception_ptr p) {
        auto raise = [](std::string message) {
            std::replace(message.begin(), message.end(), '\n', ' ');  // the CLI's one line
            PyErr_SetString(scene_error.ptr(), message.c_str());
        };
        try {
            if (p) std::rethrow_exception(p);
        } catch (const octray::SceneError& e) {
            raise(e.what());
        } catch (const octray::InvalidScene& e) {
            raise(e.what());
        }
    });
    py::class_<SceneHandle, std::shared_ptr<SceneHandle>> cls(m, "_Scene");
    bind_scene(m, cls);
    bind_rays(cls);
    bind_harness(m, cls);
}
