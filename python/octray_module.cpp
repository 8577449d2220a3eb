// python/octray_module.cpp — the Python module's core (docs/python.md): Scene
// (from a JSON file or a dict), rays in numpy arrays through the packet
// kernels, whole images, the tone map. The harnesses (verify, errtime,
// stability) and info() are in octray_harness.cpp.
//
// Every C++ exception stops at this boundary: octray::SceneError and
// octray::InvalidScene become octray.SceneError (a ValueError) with the CLI's
// one-line message; pybind11 turns the rest into ValueError (invalid_argument),
// MemoryError (bad_alloc) or RuntimeError.
#include "octray_module.hpp"

#include "image_io.hpp"
#include "scene_loader.hpp"

#include <octray/kernels.hpp>
#include <octray/reference.hpp>
#include <octray/render.hpp>
#include <octray/threads.hpp>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <thread>
#include <vector>

namespace octray::python {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// ---- arguments ---------------------------------------------------------------

Path packet_path(const std::string& path) {
    if (path == "simd") return Path::simd;
    if (path == "scalar") return Path::scalar;
    throw py::value_error("path: expected 'simd' or 'scalar', got '" + path + "'");
}

int thread_count(int threads) { return resolve_threads(checked_threads(threads)); }

// An (N, 3) array of a float dtype, read in place: float32 and float64 at any
// strides; other float dtypes (float16, longdouble) converted once to float64.
struct Vec3Array {
    py::array array;  // keeps the data alive
    const char* base = nullptr;
    py::ssize_t s0 = 0, s1 = 0;
    bool f64 = false;
    std::size_t n = 0;

    template <class T>
    float get(std::size_t i, int c) const {
        return static_cast<float>(*reinterpret_cast<const T*>(base + py::ssize_t(i) * s0 + c * s1));
    }
};

std::string shape_str(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t k = 0; k < a.ndim(); ++k) s += (k ? ", " : "") + std::to_string(a.shape(k));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

Vec3Array vec3_array(const py::handle& obj, const char* name) {
    py::module_ np = py::module_::import("numpy");
    py::array a;
    if (py::isinstance<py::array>(obj)) {
        a = py::reinterpret_borrow<py::array>(obj);
    } else {
        try {
            a = np.attr("asarray")(obj, "dtype"_a = "float64");
        } catch (py::error_already_set& e) {
            throw py::type_error(std::string(name) + ": expected an (N, 3) array of floats, got " +
                                 std::string(py::str(py::type::of(obj).attr("__name__"))));
        }
    }
    const char kind = a.dtype().kind();
    if (kind != 'f')
        throw py::type_error(std::string(name) + ": expected a floating-point array, got dtype " +
                             std::string(py::str(a.dtype())));
    if (a.ndim() != 2 || a.shape(1) != 3)
        throw py::value_error(std::string(name) + ": expected an (N, 3) array, got shape " + shape_str(a));
    if (!a.dtype().is(py::dtype::of<float>()) && !a.dtype().is(py::dtype::of<double>()))
        a = np.attr("asarray")(a, "dtype"_a = "float64");
    Vec3Array v;
    v.array = a;
    v.base = static_cast<const char*>(a.data());
    v.s0 = a.strides(0);
    v.s1 = a.strides(1);
    v.f64 = a.dtype().is(py::dtype::of<double>());
    v.n = std::size_t(a.shape(0));
    return v;
}

struct RayInput {
    Vec3Array o, d;
    float tmin = 0, tmax = kInf;
    std::size_t n = 0;
    std::size_t packets = 0;
};

RayInput ray_input(const py::handle& origins, const py::handle& directions, double tmin, double tmax) {
    RayInput in;
    in.o = vec3_array(origins, "origins");
    in.d = vec3_array(directions, "directions");
    if (in.o.n != in.d.n)
        throw py::value_error("directions: expected " + std::to_string(in.o.n) + " rays (as origins), got " +
                              std::to_string(in.d.n));
    if (std::isnan(tmin)) throw py::value_error("tmin: must not be NaN");
    if (std::isnan(tmax)) throw py::value_error("tmax: must not be NaN");
    in.tmin = float(tmin);
    in.tmax = float(tmax);
    in.n = in.o.n;
    in.packets = (in.n + 7) / 8;
    return in;
}

// Fills packet p with rays 8p .. 8p+7 in the caller's order; lanes past the
// end are inactive. Returns the lanes used.
template <class TO, class TD>
int pack(const RayInput& in, std::size_t p, RayPacket8& rp) {
    const std::size_t base = p * 8;
    const int lanes = int(std::min<std::size_t>(8, in.n - base));
    for (int i = 0; i < 8; ++i) {
        if (i < lanes) {
            const std::size_t r = base + std::size_t(i);
            rp.ox[i] = in.o.get<TO>(r, 0), rp.oy[i] = in.o.get<TO>(r, 1), rp.oz[i] = in.o.get<TO>(r, 2);
            rp.dx[i] = in.d.get<TD>(r, 0), rp.dy[i] = in.d.get<TD>(r, 1), rp.dz[i] = in.d.get<TD>(r, 2);
            rp.active[i] = 1;
        } else {
            rp.ox[i] = rp.oy[i] = rp.oz[i] = 0;
            rp.dx[i] = rp.dy[i] = 0, rp.dz[i] = 1;
            rp.active[i] = 0;
        }
        rp.tmin[i] = in.tmin;
        rp.tmax[i] = in.tmax;
        rp.pixel[i] = 0;
    }
    return lanes;
}

// Runs fn(p0, p1, thread) over packet ranges on `threads` threads (the
// calling thread takes the first range), the GIL released. Returns nothing;
// fn must not throw (the kernels are noexcept).
template <class Fn>
void parallel_packets(std::size_t packets, int threads, Fn&& fn) {
    // Fewer than ~64 packets a thread is not worth a thread.
    const std::size_t most = std::max<std::size_t>(1, packets / 64);
    const int t = int(std::min<std::size_t>(std::size_t(threads), most));
    py::gil_scoped_release release;
    if (t <= 1) {
        fn(std::size_t(0), packets, 0);
        return;
    }
    std::vector<std::thread> pool;
    auto range = [&](int k) { return packets * std::size_t(k) / std::size_t(t); };
    for (int k = 1; k < t; ++k) pool.emplace_back([&, k] { fn(range(k), range(k + 1), k); });
    fn(range(0), range(1), 0);
    for (std::thread& th : pool) th.join();
}

template <class Fn>
void with_types(const RayInput& in, Fn&& fn) {
    if (in.o.f64 && in.d.f64) fn(double{}, double{});
    else if (in.o.f64) fn(double{}, float{});
    else if (in.d.f64) fn(float{}, double{});
    else fn(float{}, float{});
}

// An array that owns a std::vector (no copy).
template <class T>
py::array_t<T> owning_array(std::vector<T>&& v, std::vector<py::ssize_t> shape) {
    auto* heap = new std::vector<T>(std::move(v));
    py::capsule owner(heap, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    return py::array_t<T>(shape, heap->data(), owner);
}

}  // namespace

// ---- Scene -------------------------------------------------------------------

int checked_threads(int threads) {
    if (threads < 0 || threads > 1024)
        throw py::value_error("threads: must be in [0, 1024] (0 = every core), got " + std::to_string(threads));
    return threads;
}

SceneHandle::SceneHandle(Scene s, std::string src) : scene(std::make_shared<const Scene>(std::move(s))), source(std::move(src)) {
    compiled = compile(*scene);
}

std::shared_ptr<SceneHandle> load(const std::string& path) {
    py::gil_scoped_release release;
    return std::make_shared<SceneHandle>(load_scene(path), path);
}

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
    return std::make_shared<SceneHandle>(parse_scene(text, "", base_dir, meshes), "");
}

namespace {

py::dict intersect(const SceneHandle& s, const py::handle& origins, const py::handle& directions, double tmin,
                   double tmax, const std::string& path, int threads) {
    const RayInput in = ray_input(origins, directions, tmin, tmax);
    const Kernel k = select_kernel(s.compiled, packet_path(path));
    const int nt = thread_count(threads);
    py::array_t<float> t(py::ssize_t(in.n));
    py::array_t<std::int32_t> prim(py::ssize_t(in.n));
    py::array_t<float> normal({py::ssize_t(in.n), py::ssize_t(3)});
    float* tp = t.mutable_data();
    std::int32_t* pp = prim.mutable_data();
    float* np_ = normal.mutable_data();
    std::vector<long long> masked(std::size_t(std::max(1, nt)), 0);
    with_types(in, [&](auto o_type, auto d_type) {
        using TO = decltype(o_type);
        using TD = decltype(d_type);
        parallel_packets(in.packets, nt, [&](std::size_t p0, std::size_t p1, int thread) {
            RayPacket8 rp;
            HitPacket8 hp;
            long long m = 0;
            for (std::size_t p = p0; p < p1; ++p) {
                const int lanes = pack<TO, TD>(in, p, rp);
                m += k.intersect(s.compiled, rp, hp);
                const std::size_t base = p * 8;
                for (int i = 0; i < lanes; ++i) {
                    const std::size_t r = base + std::size_t(i);
                    const bool hit = hp.hit[i] != 0;
                    tp[r] = hit ? hp.t[i] : kInf;
                    pp[r] = hit ? hp.primitive[i] : -1;
                    np_[3 * r] = hit ? hp.nx[i] : 0.0f;
                    np_[3 * r + 1] = hit ? hp.ny[i] : 0.0f;
                    np_[3 * r + 2] = hit ? hp.nz[i] : 0.0f;
                }
            }
            masked[std::size_t(thread)] = m;
        });
    });
    long long total = 0;
    for (long long m : masked) total += m;
    py::dict out;
    out["t"] = t;
    out["primitive"] = prim;
    out["normal"] = normal;
    out["masked"] = total;
    return out;
}

py::array_t<bool> occluded(const SceneHandle& s, const py::handle& origins, const py::handle& directions, double tmin,
                           double tmax, const std::string& path, int threads) {
    const RayInput in = ray_input(origins, directions, tmin, tmax);
    const Kernel k = select_kernel(s.compiled, packet_path(path));
    const int nt = thread_count(threads);
    py::array_t<bool> out(py::ssize_t(in.n));
    bool* op = out.mutable_data();
    with_types(in, [&](auto o_type, auto d_type) {
        using TO = decltype(o_type);
        using TD = decltype(d_type);
        parallel_packets(in.packets, nt, [&](std::size_t p0, std::size_t p1, int) {
            RayPacket8 rp;
            alignas(32) std::int32_t occ[8];
            for (std::size_t p = p0; p < p1; ++p) {
                const int lanes = pack<TO, TD>(in, p, rp);
                k.occluded(s.compiled, rp, occ);
                for (int i = 0; i < lanes; ++i) op[p * 8 + std::size_t(i)] = occ[i] != 0;
            }
        });
    });
    return out;
}

// The camera's rays, pixel by pixel, rows top first: the camera kernel's floats.
py::tuple camera_rays(const SceneHandle& s) {
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

// `octray render --hdr` (tools/cmd_render.cpp), step for step.
py::array_t<float> render(const SceneHandle& s, const std::string& path, const py::object& width_obj, int threads) {
    if (path != "reference") packet_path(path);
    int width = 0;
    if (!width_obj.is_none()) {
        width = width_obj.cast<int>();
        if (width < 1 || width > kMaxImageSide)
            throw py::value_error("width: must be in [1, " + std::to_string(kMaxImageSide) + "], got " +
                                  std::to_string(width));
    }
    const int nt = thread_count(threads);
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
    if (path == "reference") {
        const Image<double> hdr = reference::render(*scene);
        rgb.resize(hdr.rgb.size());
        for (std::size_t k = 0; k < rgb.size(); ++k) rgb[k] = static_cast<float>(hdr.rgb[k]);  // as write_pfm stores it
    } else {
        CompileOptions options;
        options.threads = nt;
        const PacketScene rebuilt = width > 0 ? compile(*scene, options) : PacketScene();
        const PacketScene& packet = width > 0 ? rebuilt : s.compiled;
        const Kernel kernel = select_kernel(packet, packet_path(path));
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
    cls.def("intersect", &intersect, "origins"_a, "directions"_a, "tmin"_a = 0.0,
            "tmax"_a = std::numeric_limits<double>::infinity(), py::kw_only(), "path"_a = "simd", "threads"_a = 0);
    cls.def("occluded", &occluded, "origins"_a, "directions"_a, "tmin"_a = 0.0,
            "tmax"_a = std::numeric_limits<double>::infinity(), py::kw_only(), "path"_a = "simd", "threads"_a = 0);
    cls.def("camera_rays", &camera_rays);
    cls.def("render", &render, "path"_a = "simd", "width"_a = py::none(), "threads"_a = 0);
    cls.def("tonemap", &tonemap, "hdr"_a, "path"_a = "simd");
    cls.def_property_readonly("width", [](const SceneHandle& s) { return s.compiled.width(); });
    cls.def_property_readonly("height", [](const SceneHandle& s) { return s.compiled.height(); });
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
    bind_harness(m, cls);
}
