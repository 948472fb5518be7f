#pragma once
// What render_snapshot shows of a frame: the view axis (the camera looks down it; the picture's
// horizontal and vertical are the other two axes), the slab of a 3D box to cut out (--slice AXIS
// POSITION THICKNESS: only the particles whose centres lie in it, so the interior is seen), and
// the force network as tubes whose radius follows the normal force.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

namespace viz {

/// A slab across the box: centres with |x[axis] - position| <= thickness / 2 are inside.
struct Slice {
    int axis = -1;           ///< 0, 1, 2 for x, y, z; -1: no slice (the whole frame, seen along z)
    bool middle = false;     ///< position "mid": the middle of each frame's particles along the axis
    double position = 0.0;   ///< m
    double thickness = 0.0;  ///< m

    bool active() const { return axis >= 0; }
    bool contains(const double x[3]) const { return !active() || std::abs(x[axis] - position) <= 0.5 * thickness; }
};

/// --slice AXIS POSITION THICKNESS as given on the command line; throws what is wrong.
inline Slice parse_slice(const std::vector<std::string>& words) {
    Slice s;
    if (words.empty()) return s;
    const std::string axes = "xyz";
    if (words.size() != 3 || words[0].size() != 1 || axes.find(words[0][0]) == std::string::npos)
        throw std::invalid_argument("--slice takes AXIS POSITION THICKNESS, AXIS one of x, y, z (e.g. --slice y mid 0.004)");
    s.axis = static_cast<int>(axes.find(words[0][0]));
    auto number = [](const std::string& w, const char* what) {
        char* end = nullptr;
        const double v = std::strtod(w.c_str(), &end);
        if (w.empty() || *end != '\0' || !std::isfinite(v))
            throw std::invalid_argument(std::string("--slice ") + what + " '" + w + "' is not a number");
        return v;
    };
    s.middle = words[1] == "mid";
    if (!s.middle) s.position = number(words[1], "POSITION");
    s.thickness = number(words[2], "THICKNESS");
    if (!(s.thickness > 0.0))
        throw std::invalid_argument("--slice THICKNESS " + words[2] + " must be above zero (m; e.g. two particle diameters)");
    return s;
}

/// The world axes drawn as the picture's horizontal, vertical and depth (towards the camera):
/// seen along z without a slice or with one across z (x right, y up), along y across y (x
/// right, z up: the loading axis of the 3D box stays vertical), along x across x (y right, z up).
inline std::array<int, 3> image_axes(const Slice& s) {
    switch (s.axis) {
        case 0: return {1, 2, 0};
        case 1: return {0, 2, 1};
        default: return {0, 1, 2};
    }
}

/// A point in picture coordinates (horizontal, vertical, depth).
inline std::array<double, 3> to_image(const double x[3], const std::array<int, 3>& axes) {
    return {x[axes[0]], x[axes[1]], x[axes[2]]};
}

/// The particles of `frame` whose centres lie in the slab, with their point data, in picture
/// coordinates.
inline vtkSmartPointer<vtkPolyData> particles_in_view(vtkPolyData* frame, const Slice& slice) {
    const auto axes = image_axes(slice);
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    auto shown = vtkSmartPointer<vtkPolyData>::New();
    shown->GetPointData()->CopyAllocate(frame->GetPointData());
    vtkNew<vtkCellArray> vertices;
    for (vtkIdType i = 0; i < frame->GetNumberOfPoints(); ++i) {
        double x[3];
        frame->GetPoint(i, x);
        if (!slice.contains(x)) continue;
        const vtkIdType k = points->InsertNextPoint(to_image(x, axes).data());
        shown->GetPointData()->CopyData(frame->GetPointData(), i, k);
        vertices->InsertNextCell(1, &k);
    }
    shown->SetPoints(points);
    shown->SetVerts(vertices);
    return shown;
}

/// The walls in picture coordinates; with a slice, those parallel to the picture (every corner at
/// one depth) are left out: they would cover the slab.
inline vtkSmartPointer<vtkPolyData> walls_in_view(vtkPolyData* walls, const Slice& slice) {
    const auto axes = image_axes(slice);
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    vtkNew<vtkCellArray> lines, polygons;
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < walls->GetNumberOfCells(); ++c) {
        walls->GetCellPoints(c, ids);
        std::vector<vtkIdType> corners;
        double depth_lo = 1e300, depth_hi = -1e300;
        for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) {
            double x[3];
            walls->GetPoint(ids->GetId(k), x);
            depth_lo = std::min(depth_lo, x[axes[2]]);
            depth_hi = std::max(depth_hi, x[axes[2]]);
            corners.push_back(points->InsertNextPoint(to_image(x, axes).data()));
        }
        if (slice.active() && corners.size() > 2 && depth_hi - depth_lo <= 1e-12 * (std::abs(depth_lo) + 1.0)) continue;
        (corners.size() == 2 ? lines : polygons)->InsertNextCell(static_cast<vtkIdType>(corners.size()), corners.data());
    }
    auto shown = vtkSmartPointer<vtkPolyData>::New();
    shown->SetPoints(points);
    shown->SetLines(lines);
    shown->SetPolys(polygons);
    return shown;
}

/// The force network of a contacts file (a line per contact with cell data normal_force) in
/// picture coordinates: each contact whose midpoint lies in the slab and that presses (f_n > 0),
/// as a line with point data "tube_radius" = widest f_n / largest (for vtkTubeFilter's radius by
/// absolute scalar). `largest` returns the largest normal force shown (0 if none).
inline vtkSmartPointer<vtkPolyData> network_in_view(vtkPolyData* contacts, const Slice& slice, double widest, double& largest) {
    const auto axes = image_axes(slice);
    vtkDataArray* force = contacts->GetCellData()->GetArray("normal_force");
    if (!force) throw std::invalid_argument("the contacts file has no normal_force cell data (not a contacts .vtp?)");
    struct Line {
        std::array<double, 3> a, b;
        double force;
    };
    std::vector<Line> shown_lines;
    largest = 0.0;
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < contacts->GetNumberOfCells(); ++c) {
        contacts->GetCellPoints(c, ids);
        const double fn = force->GetTuple1(c);
        if (ids->GetNumberOfIds() != 2 || !(fn > 0.0)) continue;
        double a[3], b[3];
        contacts->GetPoint(ids->GetId(0), a);
        contacts->GetPoint(ids->GetId(1), b);
        const double mid[3] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
        if (!slice.contains(mid)) continue;
        shown_lines.push_back({to_image(a, axes), to_image(b, axes), fn});
        largest = std::max(largest, fn);
    }
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    vtkNew<vtkCellArray> lines;
    vtkNew<vtkDoubleArray> radius;
    radius->SetName("tube_radius");
    for (const auto& l : shown_lines) {
        const vtkIdType ends[2] = {points->InsertNextPoint(l.a.data()), points->InsertNextPoint(l.b.data())};
        lines->InsertNextCell(2, ends);
        for (int k = 0; k < 2; ++k) radius->InsertNextValue(widest * l.force / largest);
    }
    auto network = vtkSmartPointer<vtkPolyData>::New();
    network->SetPoints(points);
    network->SetLines(lines);
    network->GetPointData()->SetScalars(radius);
    return network;
}

}  // namespace viz
