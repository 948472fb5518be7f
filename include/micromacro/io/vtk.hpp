#pragma once
// VTK output for ParaView (optional part: needs VTK's CommonCore, CommonDataModel and IOXML).
//
//   particles.vtp  points at the centres (double precision; 2D on the plane z = 0) with point
//                  data radius, velocity, angular_velocity (rotating scenes), force,
//                  potential_energy (Simulation::potential_energy_per_particle), kinetic_energy,
//                  coordination and the particle stress sigma^p = 1/V^p sum_c (r_p - x_c) (x) f_c,
//                  and as field data the frame's own numbers (ParticleFrame::values);
//   contacts.vtp   one line per contact (centre to centre; centre to contact point for a wall)
//                  with cell data normal_force, tangential_force, overlap, sliding;
//   walls.vtp      one quad (3D) or line (2D) per wall spanning the box, with its force;
//   *.pvd          a collection with the simulated time of every file, so ParaView opens the
//                  series at once;
//   *.pvtp         the summary of a data set written in pieces (one per MPI rank), which
//                  ParaView opens as one.
// Files are VTK XML, binary, compressed, appended; each is written to a temporary name and
// renamed, so a reader never sees half a file. A missing or unwritable directory is an error.
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkType.h>
#include <vtkXMLPolyDataWriter.h>

#include "micromacro/averaging/snapshot.hpp"
#include "micromacro/averaging/tensor.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/engine/snapshot.hpp"
#include "micromacro/io/vtk_messages.hpp"
#include "micromacro/io/whole_file.hpp"
#include "micromacro/particles/particles.hpp"

namespace micromacro::io {

namespace detail {
/// A point or vector in VTK's 3D space: 2D scenes lie in the plane z = 0 (the paper's z is y).
template <int dim>
std::array<double, 3> xyz(const Vec<dim>& v) {
    return {v[0], v[1], dim == 3 ? v[dim - 1] : 0.0};
}

inline vtkSmartPointer<vtkDoubleArray> array(const char* name, int components, vtkIdType tuples) {
    auto a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(name);
    a->SetNumberOfComponents(components);
    a->SetNumberOfTuples(tuples);
    return a;
}

inline void check_directory(const std::filesystem::path& path) {
    const auto dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
    if (!std::filesystem::is_directory(dir))
        micromacro::detail::throw_input_error("cannot write ", path.string(), ": the directory ", dir.string(),
                                              " does not exist; create it first");
}

inline void write_polydata(vtkPolyData* data, const std::filesystem::path& path) {
    check_directory(path);
    const std::filesystem::path partial = path.string() + ".partial";
    vtkNew<vtkXMLPolyDataWriter> writer;
    writer->SetFileName(partial.string().c_str());
    writer->SetInputData(data);
    writer->SetDataModeToAppended();
    writer->SetCompressorTypeToZLib();
    writer->EncodeAppendedDataOff();  // raw binary
    const VtkMessages vtk_said(writer);  // quoted in the message, not printed by VTK first
    const bool wrote = writer->Write() == 1;
    finish_vtk_write(writer, wrote, vtk_said, partial, path);
}
}  // namespace detail

/// Particle data for one frame (everything the particle file holds), built from a simulation by
/// particle_frame() or filled by hand.
template <int dim>
struct ParticleFrame {
    std::vector<Vec<dim>> position, velocity, force;
    std::vector<std::array<double, 3>> angular_velocity;  ///< empty without rotation; 2D: (0, 0, w)
    std::vector<double> radius, potential_energy, kinetic_energy;
    std::vector<int> coordination;
    std::vector<Tensor2<dim>> stress;
    std::vector<long long> id;  ///< the particles' ids (empty: not written); indices change when the engine sorts
    /// Numbers of the whole frame (the biaxial program's eps_zz, for one), written as field data:
    /// ParaView lists them, render_snapshot prints them on the picture.
    std::vector<std::pair<std::string, double>> values;

    /// Keeps the first n particles (a process's own, before the ghosts it holds).
    void keep_first(std::size_t n) {
        for (auto* v : {&position, &velocity, &force}) v->resize(n);
        for (auto* v : {&radius, &potential_energy, &kinetic_energy}) v->resize(n);
        coordination.resize(n), stress.resize(n);
        if (!angular_velocity.empty()) angular_velocity.resize(n);
        if (!id.empty()) id.resize(n);
    }
};

/// The frame of a simulation at its present state.
template <class Sim>
ParticleFrame<Sim::dimension> particle_frame(const Sim& sim) {
    constexpr int dim = Sim::dimension;
    const auto s = take_snapshot(sim);
    ParticleFrame<dim> f;
    const auto& p = sim.particles();
    f.position = p.position();
    f.velocity = p.velocity();
    f.force = p.force();
    f.radius = p.radius();
    f.id.assign(p.ids().begin(), p.ids().end());
    f.potential_energy = sim.potential_energy_per_particle();
    f.kinetic_energy.resize(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) f.kinetic_energy[i] = 0.5 * p.mass()[i] * p.velocity()[i].squaredNorm();
    if constexpr (Sim::rotation) {
        const auto& w = p.template get<field::AngularVelocity>();
        const auto& I = p.template get<field::Inertia>();
        for (std::size_t i = 0; i < p.size(); ++i) {
            if constexpr (dim == 2) f.angular_velocity.push_back({0.0, 0.0, w[i]});
            else f.angular_velocity.push_back({w[i][0], w[i][1], w[i][2]});
            f.kinetic_energy[i] += 0.5 * I[i] * DimTraits<dim>::squared_norm(w[i]);
        }
    }
    f.coordination.assign(p.size(), 0);
    f.stress.assign(p.size(), Tensor2<dim>::Zero());
    for (const auto& c : s.contacts) {
        // sigma^p = 1/V^p sum (r_p - x_c) (x) f_p: i's part of the branch with the force on i,
        // j's part (pointing the other way) with the force on j (the opposite).
        const Tensor2<dim> virial = c.branch * c.force().transpose();
        ++f.coordination[c.i];
        f.stress[c.i] += c.share_i * virial / DimTraits<dim>::particle_volume(f.radius[c.i]);
        if (!c.wall) {
            ++f.coordination[c.j];
            f.stress[c.j] += (1.0 - c.share_i) * virial / DimTraits<dim>::particle_volume(f.radius[c.j]);
        }
    }
    return f;
}

/// The particle file's data set of a frame.
template <int dim>
vtkSmartPointer<vtkPolyData> particle_data(const ParticleFrame<dim>& f) {
    const auto n = static_cast<vtkIdType>(f.position.size());
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(n);
    auto radius = detail::array("radius", 1, n), velocity = detail::array("velocity", 3, n),
         force = detail::array("force", 3, n), potential = detail::array("potential_energy", 1, n),
         kinetic = detail::array("kinetic_energy", 1, n), stress = detail::array("stress", 9, n);
    vtkNew<vtkIntArray> coordination;
    coordination->SetName("coordination");
    coordination->SetNumberOfTuples(n);
    vtkNew<vtkCellArray> vertices;
    for (vtkIdType i = 0; i < n; ++i) {
        points->SetPoint(i, detail::xyz<dim>(f.position[i]).data());
        radius->SetValue(i, f.radius[i]);
        velocity->SetTuple(i, detail::xyz<dim>(f.velocity[i]).data());
        force->SetTuple(i, detail::xyz<dim>(f.force[i]).data());
        potential->SetValue(i, f.potential_energy[i]);
        kinetic->SetValue(i, f.kinetic_energy[i]);
        coordination->SetValue(i, f.coordination[i]);
        double t[9] = {};
        for (int a = 0; a < dim; ++a)
            for (int b = 0; b < dim; ++b) t[a * 3 + b] = f.stress[i](a, b);  // 2D: the xy block
        stress->SetTuple(i, t);
        vertices->InsertNextCell(1, &i);
    }
    vtkNew<vtkPolyData> data;
    data->SetPoints(points);
    data->SetVerts(vertices);
    auto* pd = data->GetPointData();
    for (auto* a : {radius.Get(), velocity.Get(), force.Get(), potential.Get(), kinetic.Get(), stress.Get()}) pd->AddArray(a);
    pd->AddArray(coordination);
    if (!f.id.empty()) {  // for following a particle from frame to frame in ParaView
        vtkNew<vtkIdTypeArray> id;
        id->SetName("id");
        id->SetNumberOfTuples(n);
        for (vtkIdType i = 0; i < n; ++i) id->SetValue(i, static_cast<vtkIdType>(f.id[i]));
        pd->AddArray(id);
    }
    if (!f.angular_velocity.empty()) {
        auto w = detail::array("angular_velocity", 3, n);
        for (vtkIdType i = 0; i < n; ++i) w->SetTuple(i, f.angular_velocity[i].data());
        pd->AddArray(w);
    }
    pd->SetActiveScalars("potential_energy");
    for (const auto& [name, value] : f.values) {
        auto a = detail::array(name.c_str(), 1, 1);
        a->SetValue(0, value);
        data->GetFieldData()->AddArray(a);
    }
    return data;
}

template <int dim>
void write_particles(const ParticleFrame<dim>& f, const std::filesystem::path& path) {
    detail::write_polydata(particle_data(f), path);
}

/// The summary file (.pvtp) of a data set written in pieces, one file per piece (`pieces`,
/// named relative to the summary's folder), each with the point and cell arrays of `piece`:
/// ParaView opens the summary as one data set. Written atomically, like every file here.
inline void write_piece_summary(vtkPolyData* piece, const std::vector<std::string>& pieces, const std::filesystem::path& path) {
    detail::check_directory(path);
    auto type = [](vtkDataArray* a) -> std::string {
        switch (a->GetDataType()) {
            case VTK_DOUBLE: return "type=\"Float64\"";
            case VTK_FLOAT: return "type=\"Float32\"";
            case VTK_INT: return "type=\"Int32\"";
            case VTK_ID_TYPE: return sizeof(vtkIdType) == 8 ? "type=\"Int64\" IdType=\"1\"" : "type=\"Int32\" IdType=\"1\"";
            default:
                micromacro::detail::throw_input_error("write_piece_summary: the array ", a->GetName(), " has VTK type ",
                                                      a->GetDataTypeAsString(), ", which the summary cannot name");
        }
    };
    auto list = [&](std::ofstream& out, vtkDataSetAttributes* data) {  // one PDataArray per array
        for (int k = 0; k < data->GetNumberOfArrays(); ++k) {
            vtkDataArray* a = data->GetArray(k);
            out << "      <PDataArray " << type(a) << " Name=\"" << a->GetName() << "\" NumberOfComponents=\""
                << a->GetNumberOfComponents() << "\"/>\n";
        }
    };
    write_whole_file(path, std::ios::out, [&](std::ofstream& out) {
        out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PPolyData\" version=\"0.1\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
            << "  <PPolyData GhostLevel=\"0\">\n    <PPointData";
        auto* pd = piece->GetPointData();
        if (pd->GetScalars()) out << " Scalars=\"" << pd->GetScalars()->GetName() << "\"";
        out << ">\n";
        list(out, pd);
        out << "    </PPointData>\n";
        if (auto* cd = piece->GetCellData(); cd->GetNumberOfArrays() > 0) {
            out << "    <PCellData>\n";
            list(out, cd);
            out << "    </PCellData>\n";
        }
        out << "    <PPoints>\n      <PDataArray " << type(piece->GetPoints()->GetData())
            << " Name=\"Points\" NumberOfComponents=\"3\"/>\n    </PPoints>\n";
        for (const auto& file : pieces) out << "    <Piece Source=\"" << file << "\"/>\n";
        out << "  </PPolyData>\n</VTKFile>\n";
    });
}

/// The force network: a line per contact, from the first particle's centre to its partner's as the
/// branch vector sees it (minimum image) or to the wall point; every particle's centre is a point.
template <int dim>
vtkSmartPointer<vtkPolyData> contact_data(const PackingSnapshot<dim>& s) {
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    for (const auto& x : s.position) points->InsertNextPoint(detail::xyz<dim>(x).data());
    vtkNew<vtkCellArray> lines;
    const auto m = static_cast<vtkIdType>(s.contacts.size());
    auto normal = detail::array("normal_force", 1, m), tangential = detail::array("tangential_force", 3, m),
         overlap = detail::array("overlap", 1, m);
    vtkNew<vtkIntArray> sliding;
    sliding->SetName("sliding");
    sliding->SetNumberOfTuples(m);
    for (vtkIdType q = 0; q < m; ++q) {
        const auto& c = s.contacts[static_cast<std::size_t>(q)];
        vtkIdType ends[2] = {static_cast<vtkIdType>(c.i), 0};
        // The partner's end: its centre as the branch sees it (minimum image), or the wall point.
        ends[1] = points->InsertNextPoint(detail::xyz<dim>(Vec<dim>(s.position[c.i] - c.branch)).data());
        lines->InsertNextCell(2, ends);
        normal->SetValue(q, c.normal_force);
        tangential->SetTuple(q, detail::xyz<dim>(c.tangential_force).data());
        overlap->SetValue(q, c.overlap);
        sliding->SetValue(q, c.sliding ? 1 : 0);
    }
    auto data = vtkSmartPointer<vtkPolyData>::New();
    data->SetPoints(points);
    data->SetLines(lines);
    auto* cd = data->GetCellData();
    for (auto* a : {normal.Get(), tangential.Get(), overlap.Get()}) cd->AddArray(a);
    cd->AddArray(sliding);
    return data;
}

/// The force network as a file (contact_data).
template <int dim>
void write_contacts(const PackingSnapshot<dim>& s, const std::filesystem::path& path) {
    detail::write_polydata(contact_data(s), path);
}

/// The walls of a box: each as a line (2D) or quad (3D) across the box, with its force.
template <int dim>
void write_walls(const PackingSnapshot<dim>& s, const std::filesystem::path& path) {
    const auto [lo, hi] = s.bounds();
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    vtkNew<vtkCellArray> cells;
    const auto m = static_cast<vtkIdType>(s.walls.size());
    auto force = detail::array("force", 3, m);
    for (vtkIdType w = 0; w < m; ++w) {
        const auto& wall = s.walls[static_cast<std::size_t>(w)];
        const int axis = wall.axis();
        if (axis < 0) micromacro::detail::throw_input_error("write_walls draws axis-aligned walls only (wall ", w, ")");
        std::vector<vtkIdType> corner;
        const int others = dim - 1;
        for (int k = 0; k < (1 << others); ++k) {
            Vec<dim> x;
            x[axis] = wall.coordinate();
            for (int b = 0, bit = 0; b < dim; ++b)
                if (b != axis) x[b] = ((k >> bit++) & 1) ? hi[b] : lo[b];
            corner.push_back(points->InsertNextPoint(detail::xyz<dim>(x).data()));
        }
        if (dim == 3) std::swap(corner[2], corner[3]);  // quad order
        cells->InsertNextCell(static_cast<vtkIdType>(corner.size()), corner.data());
        force->SetTuple(w, detail::xyz<dim>(wall.force).data());
    }
    vtkNew<vtkPolyData> data;
    data->SetPoints(points);
    if (dim == 2) data->SetLines(cells);
    else data->SetPolys(cells);
    data->GetCellData()->AddArray(force);
    detail::write_polydata(data, path);
}

/// A periodic cell drawn by its edges: the parallelogram (2D) or parallelepiped (3D) spanned from
/// lo by the lattice vectors (the columns of Domain::lattice, tilts re-based within half a
/// period), so that a sheared cell shows its shear. The particles are kept in the box [lo, hi),
/// which the cell's images tile alike.
template <int dim>
void write_cell(const Domain<dim>& cell, const std::filesystem::path& path) {
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    for (int corner = 0; corner < (1 << dim); ++corner) {
        Vec<dim> x = cell.lo();
        for (int k = 0; k < dim; ++k)
            if ((corner >> k) & 1) x += cell.lattice().col(k);
        points->InsertNextPoint(detail::xyz<dim>(x).data());
    }
    vtkNew<vtkCellArray> edges;
    for (int corner = 0; corner < (1 << dim); ++corner)
        for (int k = 0; k < dim; ++k)
            if (!((corner >> k) & 1)) {
                const vtkIdType ends[2] = {corner, corner | (1 << k)};
                edges->InsertNextCell(2, ends);
            }
    vtkNew<vtkPolyData> data;
    data->SetPoints(points);
    data->SetLines(edges);
    detail::write_polydata(data, path);
}

/// A ParaView collection: add(time, file) for every frame, then write() (atomically).
class PvdCollection {
public:
    explicit PvdCollection(std::filesystem::path path) : path_(std::move(path)) {}
    void add(double time, const std::filesystem::path& file) { entries_.push_back({time, file.filename().string()}); }
    void write() const {
        detail::check_directory(path_);
        write_whole_file(path_, std::ios::out, [&](std::ofstream& out) {
            out.precision(17);
            out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
            for (const auto& e : entries_)
                out << "    <DataSet timestep=\"" << e.time << "\" group=\"\" part=\"0\" file=\"" << e.file << "\"/>\n";
            out << "  </Collection>\n</VTKFile>\n";
        });
    }
    std::size_t size() const { return entries_.size(); }

private:
    struct Entry {
        double time;
        std::string file;
    };
    std::filesystem::path path_;
    std::vector<Entry> entries_;
};

}  // namespace micromacro::io
