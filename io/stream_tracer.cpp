#include "io/stream_tracer.h"

#include <vtkAppendFilter.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCompositeDataIterator.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkDataSetReader.h>
#include <vtkDoubleArray.h>
#include <vtkExodusIIReader.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStreamTracer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLRectilinearGridReader.h>
#include <vtkXMLStructuredGridReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>

#include "core/error.h"
#include "io/byte_source.h"
#include "io/vtk_message_capture.h"

namespace tc {

namespace {

namespace fs = std::filesystem;

// Reads the grid; composite outputs (Exodus blocks) are appended into one unstructured grid.
vtkSmartPointer<vtkDataSet> readGrid(const std::string& path, const VtkMessageCapture& capture) {
    const std::string ext = extensionLower(path);
    vtkSmartPointer<vtkAlgorithm> reader;
    if (ext == ".vti") {
        auto r = vtkSmartPointer<vtkXMLImageDataReader>::New();
        r->SetFileName(path.c_str());
        reader = r;
    } else if (ext == ".vtr") {
        auto r = vtkSmartPointer<vtkXMLRectilinearGridReader>::New();
        r->SetFileName(path.c_str());
        reader = r;
    } else if (ext == ".vts") {
        auto r = vtkSmartPointer<vtkXMLStructuredGridReader>::New();
        r->SetFileName(path.c_str());
        reader = r;
    } else if (ext == ".vtu") {
        auto r = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
        r->SetFileName(path.c_str());
        reader = r;
    } else if (ext == ".vtk") {
        auto r = vtkSmartPointer<vtkDataSetReader>::New();
        r->SetFileName(path.c_str());
        r->ReadAllScalarsOn();
        r->ReadAllVectorsOn();
        r->ReadAllFieldsOn();
        reader = r;
    } else if (ext == ".ex2" || ext == ".exo" || ext == ".e") {
        auto r = vtkSmartPointer<vtkExodusIIReader>::New();
        r->SetFileName(path.c_str());
        r->UpdateInformation();
        r->SetAllArrayStatus(vtkExodusIIReader::NODAL, 1);
        reader = r;
    } else {
        throw InputError(path + ": dataset.trace: unsupported grid extension \"" + ext +
                         "\" (expected .vti, .vtr, .vts, .vtu, .vtk, .ex2, .exo or .e)");
    }
    reader->Update();
    if (!capture.firstError().empty()) throw InputError(path + ": VTK: " + capture.firstError());
    vtkDataObject* output = reader->GetOutputDataObject(0);
    if (auto* ds = vtkDataSet::SafeDownCast(output)) return ds;
    auto* composite = vtkCompositeDataSet::SafeDownCast(output);
    if (!composite) throw InputError(path + ": not a data set VTK can trace through");
    vtkNew<vtkAppendFilter> append;
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(composite->NewIterator());
    int blocks = 0;
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
        if (auto* block = vtkDataSet::SafeDownCast(it->GetCurrentDataObject());
            block && block->GetNumberOfPoints() > 0) {
            append->AddInputData(block);
            ++blocks;
        }
    if (blocks == 0) throw InputError(path + ": no blocks with points");
    append->Update();
    return vtkSmartPointer<vtkDataSet>(append->GetOutput());
}

std::string pointArrayNames(vtkDataSet* grid) {
    std::string names;
    for (int i = 0; i < grid->GetPointData()->GetNumberOfArrays(); ++i) {
        const char* n = grid->GetPointData()->GetArrayName(i);
        vtkDataArray* a = grid->GetPointData()->GetArray(i);
        if (!n || !a) continue;
        names += (names.empty() ? "" : ", ") + std::string(n) + " (" + std::to_string(a->GetNumberOfComponents()) + ")";
    }
    return names.empty() ? "none" : names;
}

vtkDataArray* requireArray(vtkDataSet* grid, const std::string& name, int components, const std::string& path) {
    vtkDataArray* a = grid->GetPointData()->GetArray(name.c_str());
    if (!a)
        throw InputError(path + ": dataset.trace.vector: no point array \"" + name +
                         "\" (available, with components: " + pointArrayNames(grid) + ")");
    if (a->GetNumberOfComponents() != components)
        throw InputError(path + ": dataset.trace.vector: point array \"" + name + "\" has " +
                         std::to_string(a->GetNumberOfComponents()) + " components, expected " +
                         std::to_string(components));
    return a;
}

vtkSmartPointer<vtkPolyData> makeSeeds(const TraceSpec& spec, const double bounds[6]) {
    vtkNew<vtkPoints> points;
    const glm::dvec3 lo(bounds[0], bounds[2], bounds[4]), hi(bounds[1], bounds[3], bounds[5]);
    const glm::dvec3 extent = hi - lo;
    switch (spec.seeding) {
        case TraceSpec::Seeding::Random: {
            std::mt19937 rng(spec.randomSeed);
            std::uniform_real_distribution<double> u(0.0, 1.0);
            for (int i = 0; i < spec.seeds; ++i) {
                double x = u(rng), y = u(rng), z = u(rng);
                glm::dvec3 p = lo + extent * glm::dvec3(x, y, z);
                points->InsertNextPoint(p.x, p.y, p.z);
            }
            break;
        }
        case TraceSpec::Seeding::Uniform: {
            // A lattice spacing h with (extent_x / h) (extent_y / h) ... ~ seeds over the
            // non-flat axes.
            int dims = 0;
            double volume = 1;
            for (int a = 0; a < 3; ++a)
                if (extent[a] > 0) ++dims, volume *= extent[a];
            double h = dims ? std::pow(volume / spec.seeds, 1.0 / dims) : 1.0;
            glm::ivec3 n(1);
            for (int a = 0; a < 3; ++a)
                if (extent[a] > 0) n[a] = std::max(1, int(std::lround(extent[a] / h)));
            for (int k = 0; k < n.z; ++k)
                for (int j = 0; j < n.y; ++j)
                    for (int i = 0; i < n.x; ++i) {
                        glm::dvec3 p = lo + extent * (glm::dvec3(i, j, k) + 0.5) / glm::dvec3(n);
                        points->InsertNextPoint(p.x, p.y, p.z);
                    }
            break;
        }
        case TraceSpec::Seeding::Line:
            for (int i = 0; i < spec.seeds; ++i) {
                double s = spec.seeds == 1 ? 0.5 : double(i) / double(spec.seeds - 1);
                glm::dvec3 p = glm::mix(glm::dvec3(spec.lineFrom), glm::dvec3(spec.lineTo), s);
                points->InsertNextPoint(p.x, p.y, p.z);
            }
            break;
    }
    auto seeds = vtkSmartPointer<vtkPolyData>::New();
    seeds->SetPoints(points);
    return seeds;
}

// Every numeric point array as attributes; vectors split as name_x, name_y, name_z (name_3, ...
// beyond three) plus name_magnitude, following io/line_reader.h.
void addAttributes(vtkPolyData* lines, const std::vector<vtkIdType>& order, LineSet& out) {
    vtkPointData* pd = lines->GetPointData();
    for (int a = 0; a < pd->GetNumberOfArrays(); ++a) {
        vtkDataArray* array = pd->GetArray(a);
        if (!array || !array->GetName()) continue;
        const std::string name = array->GetName();
        const int nc = array->GetNumberOfComponents();
        static const char* axis[] = {"_x", "_y", "_z"};
        std::vector<Attribute> attrs(std::size_t(nc > 1 ? nc + 1 : 1));
        for (int c = 0; c < nc; ++c) {
            // Appending (rather than "_" + to_string(c)) also avoids a GCC 12 -Wrestrict false positive.
            std::string component = name;
            if (nc > 1) {
                component += c < 3 ? axis[c] : "_";
                if (c >= 3) component += std::to_string(c);
            }
            attrs[std::size_t(c)].name = component;
        }
        if (nc > 1) attrs.back().name = name + "_magnitude";
        for (auto& attr : attrs) attr.values.reserve(order.size());
        for (vtkIdType id : order) {
            double sum = 0;
            for (int c = 0; c < nc; ++c) {
                double v = array->GetComponent(id, c);
                attrs[std::size_t(c)].values.push_back(float(v));
                sum += v * v;
            }
            if (nc > 1) attrs.back().values.push_back(float(std::sqrt(sum)));
        }
        for (auto& attr : attrs) out.attributes.push_back(std::move(attr));
    }
}

}  // namespace

bool isTraceableGridFile(const std::string& path) {
    const std::string ext = extensionLower(path);
    for (const char* e : {".vti", ".vtr", ".vts", ".vtu", ".vtk", ".ex2", ".exo", ".e"})
        if (ext == e) return true;
    return false;
}

LineSet traceStreamlines(const std::string& path, const TraceSpec& spec, CleanReport* report) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw InputError(path + ": no such file");
    VtkMessageCapture capture(/*warningsFail=*/false);
    vtkSmartPointer<vtkDataSet> read = readGrid(path, capture);

    // The grid with the vector array the tracer integrates (a shallow copy, never the reader's).
    vtkSmartPointer<vtkDataSet> grid;
    grid.TakeReference(read->NewInstance());
    grid->ShallowCopy(read);
    std::string vectorName = spec.vector;
    if (vectorName.empty()) {
        vectorName = grid->GetPointData()->GetArray("velocity") ? "trace_vector" : "velocity";
        vtkDataArray* c[3];
        for (int i = 0; i < 3; ++i) c[i] = requireArray(grid, spec.components[std::size_t(i)], 1, path);
        vtkNew<vtkDoubleArray> vector;
        vector->SetName(vectorName.c_str());
        vector->SetNumberOfComponents(3);
        vector->SetNumberOfTuples(grid->GetNumberOfPoints());
        for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
            for (int i = 0; i < 3; ++i) vector->SetComponent(p, i, c[i]->GetComponent(p, 0));
        grid->GetPointData()->AddArray(vector);
    } else {
        requireArray(grid, vectorName, 3, path);
    }

    double bounds[6];
    grid->GetBounds(bounds);
    const double diagonal = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
                                      (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
                                      (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
    vtkSmartPointer<vtkPolyData> seeds = makeSeeds(spec, bounds);

    vtkNew<vtkStreamTracer> tracer;
    tracer->SetInputData(grid);
    tracer->SetSourceData(seeds);
    tracer->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vectorName.c_str());
    tracer->SetIntegratorTypeToRungeKutta45();
    tracer->SetIntegrationStepUnit(vtkStreamTracer::CELL_LENGTH_UNIT);
    tracer->SetInitialIntegrationStep(spec.stepLength);
    // ParaView's defaults for the default step 0.2 (0.01 .. 0.5 cells). A larger maximum lets
    // RK45 take one error-free step out of a uniform field's grid on the first step, and VTK
    // 9.1 then drops the 1-point line.
    tracer->SetMinimumIntegrationStep(spec.stepLength / 20);
    tracer->SetMaximumIntegrationStep(spec.stepLength * 2.5);
    tracer->SetMaximumError(1e-6);
    tracer->SetMaximumNumberOfSteps(spec.maxSteps);
    tracer->SetMaximumPropagation(spec.maxLength > 0 ? double(spec.maxLength) : diagonal);
    tracer->SetComputeVorticity(true);
    tracer->SetIntegrationDirection(spec.direction == TraceSpec::Direction::Forward    ? vtkStreamTracer::FORWARD
                                    : spec.direction == TraceSpec::Direction::Backward ? vtkStreamTracer::BACKWARD
                                                                                       : vtkStreamTracer::BOTH);
    tracer->Update();
    if (!capture.firstError().empty()) throw InputError(path + ": VTK stream tracer: " + capture.firstError());
    vtkPolyData* traced = tracer->GetOutput();

    // Group VTK's cells by seed: with "both", a seed has a backward and a forward cell that
    // start at the seed; they become one polyline, the backward one reversed in front.
    vtkDataArray* seedIds = traced->GetCellData()->GetArray("SeedIds");
    vtkDataArray* time = traced->GetPointData()->GetArray("IntegrationTime");
    std::map<vtkIdType, std::vector<vtkIdType>> cellsBySeed;
    for (vtkIdType c = 0; c < traced->GetNumberOfCells(); ++c)
        cellsBySeed[seedIds ? vtkIdType(seedIds->GetComponent(c, 0)) : c].push_back(c);

    LineSet out;
    std::vector<vtkIdType> order;  // output vertex -> traced point id
    vtkNew<vtkIdList> ids;
    for (const auto& [seed, cells] : cellsBySeed) {
        std::vector<vtkIdType> backward, forward;
        for (vtkIdType c : cells) {
            traced->GetCellPoints(c, ids);
            // Copied id by id: GCC 12 takes a vector built from the GetPointer(0) range for a
            // pointer into the middle of an allocation (a false -Wfree-nonheap-object).
            std::vector<vtkIdType> pts(std::size_t(ids->GetNumberOfIds()));
            for (std::size_t k = 0; k < pts.size(); ++k) pts[k] = ids->GetId(vtkIdType(k));
            if (pts.empty()) continue;
            const bool isBackward = time && pts.size() > 1 && time->GetComponent(pts.back(), 0) < 0;
            if (isBackward)
                backward = std::move(pts);
            else
                forward = std::move(pts);
        }
        // The backward half reversed, then the forward half; both start at the seed: keep it once.
        const std::size_t skip = !backward.empty() && !forward.empty() ? 1 : 0;
        std::vector<vtkIdType> line;
        line.reserve(backward.size() + forward.size());
        for (auto it = backward.rbegin(); it != backward.rend(); ++it) line.push_back(*it);
        for (std::size_t i = std::min(skip, forward.size()); i < forward.size(); ++i) line.push_back(forward[i]);
        if (line.size() < 2) continue;
        for (vtkIdType id : line) {
            double p[3];
            traced->GetPoint(id, p);
            out.positions.push_back(glm::vec3(float(p[0]), float(p[1]), float(p[2])));
            order.push_back(id);
        }
        out.offsets.push_back(std::uint32_t(out.positions.size()));
    }
    addAttributes(traced, order, out);
    out.velocity = vectorName;  // "speed" is the magnitude of the traced vector, whatever its name
    CleanReport cleaned = cleanLineSet(out);
    if (report) *report = cleaned;
    if (out.polylineCount() == 0)
        throw InputError(path + ": dataset.trace: no streamlines (" + std::to_string(seeds->GetNumberOfPoints()) +
                         " seeds; seeds outside the grid or in zero velocity trace nothing)");
    return out;
}

}  // namespace tc
