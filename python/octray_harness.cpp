// python/octray_harness.cpp — Scene.info(), Scene.verify(), octray.errtime()
// and octray.stability(): the numbers of `octray info`, `verify`, `errtime` and
// `stability` (tools/cmd_*.cpp) as dicts, from the same harnesses
// (octray_harness), without the tables' text.
#include "octray_module.hpp"

#include "errtime.hpp"
#include "stability_cases.hpp"
#include "verify.hpp"

#include <octray/features.hpp>
#include <octray/kernels.hpp>
#include <octray/render.hpp>

#include <pybind11/stl.h>

#include <algorithm>

namespace octray::python {

namespace {

py::dict agreement_dict(const Agreement& a) {
    py::dict d;
    d["lanes"] = a.lanes;
    d["compared"] = a.compared;
    d["max_rel"] = a.max_rel;
    d["mean_rel"] = a.mean_rel;
    d["p99_rel"] = a.p99_rel;
    d["max_scaled"] = a.max_scaled;
    d["max_ulp"] = a.max_ulp;
    d["mismatched"] = a.mismatched;
    d["mismatched_silhouette"] = a.mismatched_silhouette;
    d["shadow_edges"] = a.shadow_edges;
    d["occlusion_grazing"] = a.occlusion_grazing;
    d["nonfinite"] = a.nonfinite;
    return d;
}

py::dict info(const SceneHandle& s) {
    const Scene& scene = *s.scene;
    const PacketScene& packet = s.compiled;
    const Features& f = packet.features();
    py::dict d;
    d["source"] = s.source;
    // A geometry-only scene's placeholder camera and material are not the caller's: None and [].
    const py::object none = py::none();
    d["width"] = s.has_camera() ? py::object(py::int_(scene.camera.width)) : none;
    d["height"] = s.has_camera() ? py::object(py::int_(scene.camera.height)) : none;
    d["camera"] = s.has_camera() ? py::object(py::str(camera_type_name(scene.camera.type))) : none;
    py::dict prims;
    for (int t = 0; t < kPrimitiveTypeCount; ++t)
        prims[kPrimitiveTypeNames[t]] = packet.count(static_cast<PrimitiveType>(t));
    d["primitives"] = prims;
    d["primitive_count"] = packet.primitive_count();
    d["objects"] = scene.objects.size();
    py::list meshes;
    for (std::size_t k = 0; k < scene.meshes.size(); ++k) {
        const Mesh& m = scene.meshes[k];
        Vec3d lo = m.vertices.front(), hi = lo;
        for (const Vec3d& v : m.vertices)
            lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)},
            hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
        py::dict md;
        md["triangles"] = m.triangle_count();
        md["vertices"] = m.vertices.size();
        md["dropped_degenerate"] = m.dropped_degenerate;
        md["geometry_id"] = s.primitives.mesh_geometry[k];
        md["material"] = s.has_materials() ? py::object(py::str(scene.materials.at(std::size_t(m.material)).name)) : none;
        md["bounds"] = py::make_tuple(py::make_tuple(lo.x, lo.y, lo.z), py::make_tuple(hi.x, hi.y, hi.z));
        meshes.append(md);
    }
    d["meshes"] = meshes;
    int attenuated = 0;
    for (const PointLight& l : scene.point_lights) attenuated += l.attenuation == Attenuation::inverse_square;
    py::dict lights;
    lights["ambient"] = bool(scene.ambient);
    lights["directional"] = scene.directional_lights.size();
    lights["point"] = int(scene.point_lights.size()) - attenuated;
    lights["point_inverse_square"] = attenuated;
    d["lights"] = lights;
    py::list materials;
    if (s.has_materials())
        for (const Material& m : scene.materials) materials.append(m.name);
    d["materials"] = materials;
    d["features"] = feature_string(f.bits);
    d["tonemap"] = tonemap_name(f.tonemap);
    d["gamma"] = scene.render.gamma;
    d["simd_supported"] = simd_supported();
    d["avx512_supported"] = avx512_supported();
    py::dict kernels;
    for (Path path : {Path::simd, Path::scalar}) kernels[path_name(path)] = select_kernel(packet, path).name();
    d["kernels"] = kernels;
    return d;
}

// `octray verify` (tools/cmd_verify.cpp): per path, the table's numbers and the verdict.
py::dict verify(const SceneHandle& s, int threads) {
    s.require("verify", true, true);
    checked_threads(threads);
    struct Row {
        Path path;
        std::string isa, kernel;
        Agreement a;
        bool pass;
    };
    std::vector<Row> rows;
    int used = 0;
    const Tolerance tol;
    {
        py::gil_scoped_release release;
        const ReferenceRender ref = render_reference(*s.scene, threads);
        for (Path path : {Path::scalar, Path::simd}) {
            const Kernel kernel = select_kernel(s.compiled, path);
            const PacketRender out = render_packet(kernel, s.compiled, threads);
            used = std::max(used, out.threads);
            const Agreement a = compare(ref, out.radiance, out.primitive);
            rows.push_back({path, kernel.isa, kernel.name(), a, a.within(tol)});
        }
    }
    py::dict d;
    bool ok = true;
    for (const Row& r : rows) {
        py::dict row = agreement_dict(r.a);
        row["isa"] = r.isa;
        row["kernel"] = r.kernel;
        row["pass"] = r.pass;
        row["verdict"] = r.pass ? "ok" : "OVER TOLERANCE";
        d[path_name(r.path)] = row;
        ok = ok && r.pass;
    }
    py::dict t;
    t["scaled_error"] = tol.scaled_error;
    t["silhouette_fraction"] = tol.silhouette_fraction;
    d["tolerance"] = t;
    d["threads"] = used;
    d["pass"] = ok;
    return d;
}

// `octray errtime` (tools/cmd_errtime.cpp): one dict per row of the table.
py::list errtime(const SceneHandle& s, int threads, int min_repetitions, int max_repetitions, double min_seconds) {
    s.require("errtime", true, true);
    checked_threads(threads);
    if (min_repetitions < 5) throw py::value_error("min_repetitions: must be >= 5, got " + std::to_string(min_repetitions));
    if (max_repetitions < min_repetitions)
        throw py::value_error("max_repetitions: must be >= min_repetitions, got " + std::to_string(max_repetitions));
    if (!(min_seconds >= 0)) throw py::value_error("min_seconds: must be >= 0");
    ErrtimeOptions o;
    o.threads = threads;
    o.min_repetitions = min_repetitions;
    o.max_repetitions = max_repetitions;
    o.min_seconds = min_seconds;
    ErrtimeReport r;
    {
        py::gil_scoped_release release;
        r = measure_errtime(*s.scene, o);
    }
    py::list out;
    for (const ErrtimePoint& p : r.points) {
        py::dict d = agreement_dict(p.agreement);
        d["path"] = path_name(p.path);
        d["precision"] = precision_name(p.precision);
        d["isa"] = p.isa;
        d["kernel"] = p.kernel;
        d["ns_per_ray"] = p.ns_per_ray;
        d["ns_min"] = p.ns_min;
        d["ns_max"] = p.ns_max;
        d["repetitions"] = p.repetitions;
        d["pareto"] = p.pareto;
        d["bound"] = p.tolerance.scaled_error;  // as `octray errtime`'s bound and verdict columns
        d["pass"] = p.within;
        d["verdict"] = p.within ? "ok" : "OVER BOUND";
        d["kappa"] = r.kappa;
        d["width"] = r.width;
        d["height"] = r.height;
        out.append(d);
    }
    return out;
}

std::string tracer_key(const stability::Tracer& t) {
    return t.naive ? std::string("naive") : std::string(path_name(t.path)) + "/" + precision_name(t.precision);
}

// `octray stability` (tools/cmd_stability.cpp): one dict per case.
py::list stability() {
    using namespace octray::stability;
    struct Cell {
        std::string key;
        Measure m;
        bool naive;
    };
    struct Row {
        const Case* c;
        std::vector<Cell> cells;
        bool ok;
    };
    std::vector<Row> rows;
    {
        py::gil_scoped_release release;
        std::vector<Tracer> tracers = kernel_tracers();
        tracers.push_back(naive_tracer());
        for (const Case& c : catalogue()) {
            Row row{&c, {}, true};
            for (const Tracer& t : tracers) {
                const Measure m = c.run(t);
                row.cells.push_back({tracer_key(t), m, t.naive});
                if (!t.naive && !m.pass) row.ok = false;
            }
            rows.push_back(std::move(row));
        }
    }
    py::list out;
    for (const Row& r : rows) {
        py::dict d;
        d["case"] = r.c->name;
        d["expectation"] = r.c->expectation;
        d["bound_text"] = r.c->bound_text;
        d["bound"] = r.c->bound;
        py::dict results;
        for (const Cell& c : r.cells) {
            py::dict cell;
            cell["error"] = c.m.error;
            cell["pass"] = c.m.pass;
            cell["note"] = c.m.note;
            results[py::str(c.key)] = cell;
        }
        d["results"] = results;
        d["pass"] = r.ok;
        d["verdict"] = r.ok ? "pass" : "FAIL";
        out.append(d);
    }
    return out;
}

}  // namespace

void bind_harness(py::module_& m, py::class_<SceneHandle, std::shared_ptr<SceneHandle>>& cls) {
    cls.def("info", &info);
    cls.def("verify", &verify, "threads"_a = 0);
    m.def("_errtime", &errtime, "scene"_a, "threads"_a = 1, "min_repetitions"_a = 5, "max_repetitions"_a = 50,
          "min_seconds"_a = 0.5);
    m.def("_stability", &stability);
}

}  // namespace octray::python
