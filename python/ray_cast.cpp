// python/ray_cast.cpp — the caller's rays through the packet kernels
// (docs/python.md): Scene.intersect, Scene.occluded and Scene.shade. Rays come
// in numpy arrays of any float dtype and layout, read in place; they are
// packed 8 at a time in the caller's order, and the packets run on threads of
// their own with the GIL released.
#include "octray_module.hpp"

#include <octray/threads.hpp>

#include <pybind11/numpy.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>
#include <vector>

namespace octray::python {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

std::string shape_str(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t k = 0; k < a.ndim(); ++k) s += (k ? ", " : "") + std::to_string(a.shape(k));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

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
    if (a.dtype().kind() != 'f')
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

// tmin or tmax: one number for every ray, or an (N,) array of numbers read in
// place (float32 and float64 at any stride; other real dtypes converted once).
// A scalar NaN is an error (it would mask off every ray); a NaN in an array
// masks off its ray alone, as a NaN in a direction does.
struct Interval {
    py::array array;
    const char* base = nullptr;  // null: `value` for every ray
    py::ssize_t stride = 0;
    bool f64 = false;
    float value = 0;

    float at(std::size_t i) const {
        if (!base) return value;
        const char* p = base + py::ssize_t(i) * stride;
        return f64 ? static_cast<float>(*reinterpret_cast<const double*>(p)) : *reinterpret_cast<const float*>(p);
    }
};

Interval interval(const py::handle& obj, const char* name, std::size_t n) {
    Interval in;
    auto scalar = [&](double v) {
        if (std::isnan(v)) throw py::value_error(std::string(name) + ": must not be NaN");
        in.value = float(v);
        return in;
    };
    if (py::isinstance<py::float_>(obj) || (py::isinstance<py::int_>(obj) && !py::isinstance<py::bool_>(obj)))
        return scalar(obj.cast<double>());
    py::module_ np = py::module_::import("numpy");
    py::array a;
    try {
        a = np.attr("asarray")(obj);
    } catch (py::error_already_set&) {
        throw py::type_error(std::string(name) + ": expected a number or an (N,) array of numbers, got " +
                             std::string(py::str(py::type::of(obj).attr("__name__"))));
    }
    const char kind = a.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u')
        throw py::type_error(std::string(name) + ": expected a number or an (N,) array of numbers, got dtype " +
                             std::string(py::str(a.dtype())));
    if (a.ndim() == 0) return scalar(np.attr("float64")(a).cast<double>());
    if (a.ndim() != 1 || std::size_t(a.shape(0)) != n)
        throw py::value_error(std::string(name) + ": expected a number or an (N,) array with N = " + std::to_string(n) +
                              " (one per ray), got shape " + shape_str(a));
    if (!a.dtype().is(py::dtype::of<float>()) && !a.dtype().is(py::dtype::of<double>()))
        a = np.attr("asarray")(a, "dtype"_a = "float64");
    in.array = a;
    in.base = static_cast<const char*>(a.data());
    in.stride = a.strides(0);
    in.f64 = a.dtype().is(py::dtype::of<double>());
    return in;
}

struct RayInput {
    Vec3Array o, d;
    Interval tmin, tmax;
    std::size_t n = 0;
    std::size_t packets = 0;
};

RayInput ray_input(const py::handle& origins, const py::handle& directions, const py::handle& tmin,
                   const py::handle& tmax) {
    RayInput in;
    in.o = vec3_array(origins, "origins");
    in.d = vec3_array(directions, "directions");
    if (in.o.n != in.d.n)
        throw py::value_error("directions: expected " + std::to_string(in.o.n) + " rays (as origins), got " +
                              std::to_string(in.d.n));
    in.n = in.o.n;
    in.tmin = interval(tmin, "tmin", in.n);
    in.tmax = interval(tmax, "tmax", in.n);
    in.packets = (in.n + 7) / 8;
    return in;
}

// Fills packet p with rays 8p .. 8p+7 in the caller's order; lanes past the
// end are inactive. A lane's pixel (the key of its ambient-occlusion samples)
// is the ray's index. Returns the lanes used.
// Fills lanes 0 .. lanes-1 of an interval array; the others get `idle`.
void fill_interval(const Interval& in, std::size_t base, int lanes, float* out, float idle) {
    if (!in.base) {
        std::fill_n(out, lanes, in.value);
    } else {
        for (int i = 0; i < lanes; ++i) out[i] = in.at(base + std::size_t(i));
    }
    std::fill(out + lanes, out + 8, idle);
}

// Rays base .. base+7 of C-contiguous (N, 3) arrays of T: a fixed stride, so
// the compiler deinterleaves with vector shuffles.
template <class T>
void pack_contiguous(const Vec3Array& a, std::size_t base, float* x, float* y, float* z) {
    const T* src = reinterpret_cast<const T*>(a.base) + 3 * base;
    for (int i = 0; i < 8; ++i) x[i] = float(src[3 * i]), y[i] = float(src[3 * i + 1]), z[i] = float(src[3 * i + 2]);
}

template <class T>
bool contiguous(const Vec3Array& a) {
    return a.s1 == py::ssize_t(sizeof(T)) && a.s0 == py::ssize_t(3 * sizeof(T));
}

template <class TO, class TD>
int pack(const RayInput& in, std::size_t p, RayPacket8& rp) {
    const std::size_t base = p * 8;
    const int lanes = int(std::min<std::size_t>(8, in.n - base));
    if (lanes == 8 && contiguous<TO>(in.o) && contiguous<TD>(in.d)) {  // most calls: numpy's default layout
        pack_contiguous<TO>(in.o, base, rp.ox, rp.oy, rp.oz);
        pack_contiguous<TD>(in.d, base, rp.dx, rp.dy, rp.dz);
        for (int i = 0; i < 8; ++i) rp.active[i] = 1, rp.pixel[i] = std::int32_t(base + std::size_t(i));
        fill_interval(in.tmin, base, 8, rp.tmin, 0.0f);
        fill_interval(in.tmax, base, 8, rp.tmax, kInf);
        return 8;
    }
    for (int i = 0; i < lanes; ++i) {
        const std::size_t r = base + std::size_t(i);
        rp.ox[i] = in.o.get<TO>(r, 0), rp.oy[i] = in.o.get<TO>(r, 1), rp.oz[i] = in.o.get<TO>(r, 2);
        rp.dx[i] = in.d.get<TD>(r, 0), rp.dy[i] = in.d.get<TD>(r, 1), rp.dz[i] = in.d.get<TD>(r, 2);
        rp.active[i] = 1;
        rp.pixel[i] = std::int32_t(r);
    }
    for (int i = lanes; i < 8; ++i) {
        rp.ox[i] = rp.oy[i] = rp.oz[i] = 0;
        rp.dx[i] = rp.dy[i] = 0, rp.dz[i] = 1;
        rp.active[i] = 0;
        rp.pixel[i] = 0;
    }
    fill_interval(in.tmin, base, lanes, rp.tmin, 0.0f);
    fill_interval(in.tmax, base, lanes, rp.tmax, kInf);
    return lanes;
}

// Runs fn(p0, p1, thread) over packet ranges on `threads` threads (the
// calling thread takes the first range), the GIL released. fn must not throw
// (the kernels are noexcept).
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

int thread_count(int threads) { return resolve_threads(checked_threads(threads)); }

// Output arrays carved from one numpy buffer (each a view of it, 64-byte
// aligned): one allocation a call, which the C library keeps and reuses from
// call to call, where seven of several MB each went back to the system when
// freed and cost a page fault every 4 KB at the next call (a tenth of the
// time of a call on a million-triangle mesh).
class OutputBuffer {
public:
    explicit OutputBuffer(std::size_t bytes) : buffer_(py::ssize_t(bytes + 64 * kMaxArrays)) {
        const auto base = reinterpret_cast<std::uintptr_t>(buffer_.mutable_data());
        offset_ = std::size_t((64 - base % 64) % 64);
    }
    template <class T>
    py::array_t<T> take(std::vector<py::ssize_t> shape) {
        std::size_t count = 1;
        for (py::ssize_t k : shape) count *= std::size_t(k);
        T* data = reinterpret_cast<T*>(buffer_.mutable_data() + offset_);
        offset_ += (count * sizeof(T) + 63) / 64 * 64;
        return py::array_t<T>(shape, data, buffer_);
    }

private:
    static constexpr std::size_t kMaxArrays = 8;
    py::array_t<std::uint8_t> buffer_;
    std::size_t offset_ = 0;
};

// The caller's rays packet by packet on `threads` threads, the GIL released:
// fn(rays, p, lanes, thread) for packet p, filled with rays 8p .. 8p+lanes-1.
// The packing loop is compiled for each pair of float32 / float64 arrays.
template <class Fn>
void for_each_packet(const RayInput& in, int threads, Fn&& fn) {
    auto run = [&](auto o_type, auto d_type) {
        using TO = decltype(o_type);
        using TD = decltype(d_type);
        parallel_packets(in.packets, threads, [&](std::size_t p0, std::size_t p1, int thread) {
            RayPacket8 rp;
            for (std::size_t p = p0; p < p1; ++p) fn(rp, p, pack<TO, TD>(in, p, rp), thread);
            _mm_sfence();  // store_out's streaming stores, before the arrays are read
        });
    };
    if (in.o.f64 && in.d.f64) run(double{}, double{});
    else if (in.o.f64) run(double{}, float{});
    else if (in.d.f64) run(float{}, double{});
    else run(float{}, float{});
}

py::dict intersect(const SceneHandle& s, const py::handle& origins, const py::handle& directions,
                   const py::handle& tmin, const py::handle& tmax, const std::string& path, const std::string& mode,
                   int threads) {
    const RayInput in = ray_input(origins, directions, tmin, tmax);
    const Kernel k = kernel_for(s, path, mode);
    const int nt = thread_count(threads);
    const auto n = py::ssize_t(in.n);
    OutputBuffer buffer(in.n * 4 * (1 + 1 + 1 + 2 + 3 + 1 + 3));
    auto t = buffer.take<float>({n}), normal = buffer.take<float>({n, 3}), uv = buffer.take<float>({n, 2}),
         gn = buffer.take<float>({n, 3});
    auto prim = buffer.take<std::int32_t>({n}), geometry = buffer.take<std::int32_t>({n}),
         primitive_id = buffer.take<std::int32_t>({n});
    const HitArrays arrays{t.mutable_data(),        prim.mutable_data(),         normal.mutable_data(),
                           geometry.mutable_data(), primitive_id.mutable_data(), uv.mutable_data(),
                           gn.mutable_data()};
    struct alignas(64) Count {  // one cache line a thread: each adds to its own
        long long n = 0;
    };
    std::vector<Count> masked(std::size_t(std::max(1, nt)));
    std::vector<HitRecorder> recorders;
    for (int j = 0; j < std::max(1, nt); ++j) recorders.emplace_back(s, arrays);
    for_each_packet(in, nt, [&](const RayPacket8& rp, std::size_t p, int lanes, int thread) {
        HitPacket8 hp;
        HitFields8 fields;
        masked[std::size_t(thread)].n += k.intersect_fields(s.compiled, rp, hp, fields);
        recorders[std::size_t(thread)].push(hp, fields, lanes, p * 8);
    });
    for (HitRecorder& r : recorders) r.finish();  // each thread's last chunks
    long long total = 0;
    for (const Count& m : masked) total += m.n;
    py::dict out;
    out["t"] = t;
    out["geometry_id"] = geometry;
    out["primitive_id"] = primitive_id;
    out["uv"] = uv;
    out["geometric_normal"] = gn;
    out["primitive"] = prim;
    out["normal"] = normal;
    out["masked"] = total;
    return out;
}

py::array_t<bool> occluded(const SceneHandle& s, const py::handle& origins, const py::handle& directions,
                           const py::handle& tmin, const py::handle& tmax, const std::string& path,
                           const std::string& mode, int threads) {
    const RayInput in = ray_input(origins, directions, tmin, tmax);
    const Kernel k = kernel_for(s, path, mode);
    py::array_t<bool> out(py::ssize_t(in.n));
    bool* op = out.mutable_data();
    for_each_packet(in, thread_count(threads), [&](const RayPacket8& rp, std::size_t p, int lanes, int) {
        alignas(32) std::int32_t occ[8];
        k.occluded(s.compiled, rp, occ);
        for (int i = 0; i < lanes; ++i) op[p * 8 + std::size_t(i)] = occ[i] != 0;
    });
    return out;
}

// Kernel::shade on the caller's rays, as render_rows does on camera rays:
// intersect, then shade, packet by packet.
py::array_t<float> shade(const SceneHandle& s, const py::handle& origins, const py::handle& directions,
                         const py::handle& tmin, const py::handle& tmax, const std::string& path,
                         const std::string& mode, int threads) {
    s.require("shade", false, true);
    const RayInput in = ray_input(origins, directions, tmin, tmax);
    const Kernel k = kernel_for(s, path, mode);
    py::array_t<float> out({py::ssize_t(in.n), py::ssize_t(3)});
    float* op = out.mutable_data();
    for_each_packet(in, thread_count(threads), [&](const RayPacket8& rp, std::size_t p, int lanes, int) {
        HitPacket8 hp;
        ColorPacket8 c;
        k.intersect(s.compiled, rp, hp);
        k.shade(s.compiled, rp, hp, c);
        for (int i = 0; i < lanes; ++i) {
            float* rgb = op + 3 * (p * 8 + std::size_t(i));
            rgb[0] = c.r[i], rgb[1] = c.g[i], rgb[2] = c.b[i];
        }
    });
    return out;
}

}  // namespace

void bind_rays(py::class_<SceneHandle, std::shared_ptr<SceneHandle>>& cls) {
    const double inf = std::numeric_limits<double>::infinity();
    cls.def("intersect", &intersect, "origins"_a, "directions"_a, "tmin"_a = 0.0, "tmax"_a = inf, py::kw_only(),
            "path"_a = "simd", "mode"_a = "exact", "threads"_a = 0);
    cls.def("occluded", &occluded, "origins"_a, "directions"_a, "tmin"_a = 0.0, "tmax"_a = inf, py::kw_only(),
            "path"_a = "simd", "mode"_a = "exact", "threads"_a = 0);
    cls.def("shade", &shade, "origins"_a, "directions"_a, "tmin"_a = 0.0, "tmax"_a = inf, py::kw_only(),
            "path"_a = "simd", "mode"_a = "exact", "threads"_a = 0);
}

}  // namespace octray::python
