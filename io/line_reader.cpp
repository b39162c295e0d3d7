#include "io/line_reader.h"

#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkErrorCode.h>
#include <vtkFloatArray.h>
#include <vtkGenericDataObjectReader.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPPolyDataReader.h>
#include <vtkXMLPUnstructuredGridReader.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <numeric>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/byte_source.h"
#include "io/line_formats.h"
#include "io/vtk_message_capture.h"

namespace tc {

namespace {

// vtkErrorCode::GetStringFromErrorCode lives in VTK::CommonMisc, which tubecast does not link;
// the enum is header-only.
std::string errorCodeText(unsigned long code) {
    switch (code) {
        case vtkErrorCode::FileNotFoundError:
            return "file not found";
        case vtkErrorCode::CannotOpenFileError:
            return "cannot open file";
        case vtkErrorCode::UnrecognizedFileTypeError:
            return "unrecognized file type";
        case vtkErrorCode::PrematureEndOfFileError:
            return "premature end of file";
        case vtkErrorCode::FileFormatError:
            return "file format error";
        case vtkErrorCode::OutOfDiskSpaceError:
            return "out of disk space";
        default:
            return "error code " + std::to_string(code);
    }
}

// The numeric point-data arrays of a data set as scalar Attributes (see line_reader.h): makes
// the (empty) attributes, then append(id, attributes) adds one point's values to each.
class PointDataColumns {
public:
    // Arrays for which `skip` returns true are left out (the particle path takes radii and
    // colours out of the point data).
    template <class Skip>
    PointDataColumns(vtkDataSet* data, std::vector<Attribute>& attributes, Skip skip) {
        const vtkIdType pointCount = data->GetNumberOfPoints();
        vtkPointData* pd = data->GetPointData();
        for (int i = 0; pd && i < pd->GetNumberOfArrays(); ++i) {
            vtkDataArray* array = pd->GetArray(i);  // null for string arrays
            if (!array || array->GetNumberOfTuples() != pointCount || skip(array)) continue;
            m_arrays.push_back(array);
            std::string name = array->GetName() && *array->GetName() ? array->GetName() : "array" + std::to_string(i);
            const int k = array->GetNumberOfComponents();
            if (k == 1) {
                attributes.push_back({name, {}});
                continue;
            }
            static const char* const xyz[] = {"x", "y", "z"};
            for (int c = 0; c < k; ++c) {
                std::string component = c < 3 ? std::string(xyz[c]) : std::to_string(c);
                attributes.push_back({name + '_' + component, {}});
            }
            attributes.push_back({name + "_magnitude", {}});
        }
    }
    PointDataColumns(vtkDataSet* data, std::vector<Attribute>& attributes)
        : PointDataColumns(data, attributes, [](vtkDataArray*) { return false; }) {}

    void append(vtkIdType id, std::vector<Attribute>& attributes) const {
        std::size_t a = 0;
        for (vtkDataArray* array : m_arrays) {
            const int k = array->GetNumberOfComponents();
            if (k == 1) {
                attributes[a++].values.push_back(float(array->GetComponent(id, 0)));
                continue;
            }
            double sum = 0.0;
            for (int c = 0; c < k; ++c) {
                double v = array->GetComponent(id, c);
                sum += v * v;
                attributes[a++].values.push_back(float(v));
            }
            attributes[a++].values.push_back(float(std::sqrt(sum)));
        }
    }

private:
    std::vector<vtkDataArray*> m_arrays;
};

// Gathers positions and point data of the cells' points into `lines`, one polyline per cell.
class LineSetBuilder {
public:
    LineSetBuilder(const std::string& path, vtkDataSet* data)
        : m_path(path), m_data(data), m_pointCount(data->GetNumberOfPoints()), m_columns(data, m_lines.attributes) {}

    void addCell(vtkIdType cell, vtkIdType n, const vtkIdType* ids) {
        vtkPoints* points = pointsOf();
        for (vtkIdType j = 0; j < n; ++j) {
            const vtkIdType id = ids[j];
            if (id < 0 || id >= m_pointCount)
                throw InputError(m_path + ": cell " + std::to_string(cell) + ": point id " + std::to_string(id) +
                                 " out of range (" + std::to_string(m_pointCount) + " points)");
            double p[3];
            points->GetPoint(id, p);
            m_lines.positions.emplace_back(float(p[0]), float(p[1]), float(p[2]));
            m_columns.append(id, m_lines.attributes);
        }
        if (m_lines.positions.size() > std::numeric_limits<std::uint32_t>::max())
            throw InputError(m_path + ": more than 2^32 polyline vertices are not supported");
        m_lines.offsets.push_back(std::uint32_t(m_lines.positions.size()));
    }

    LineSet take() { return std::move(m_lines); }

private:
    vtkPoints* pointsOf() {
        if (auto* poly = vtkPolyData::SafeDownCast(m_data)) return poly->GetPoints();
        return vtkPointSet::SafeDownCast(m_data)->GetPoints();
    }

    const std::string& m_path;
    vtkDataSet* m_data;
    vtkIdType m_pointCount = 0;
    LineSet m_lines;  // before m_columns, which adds its attributes
    PointDataColumns m_columns;
};

[[noreturn]] void throwNoPolylines(const std::string& path, vtkDataSet* data, vtkIdType otherCells) {
    throw InputError(path + ": no polylines (" + std::to_string(data->GetNumberOfPoints()) + " points, " +
                     std::to_string(otherCells) + " cells of other types)");
}

// Line and polyline cells of a PolyData or UnstructuredGrid (0 for other data sets).
vtkIdType lineCellCount(vtkDataObject* object) {
    if (auto* poly = vtkPolyData::SafeDownCast(object))
        return poly->GetLines() ? poly->GetLines()->GetNumberOfCells() : 0;
    vtkIdType lineCells = 0;
    if (auto* grid = vtkUnstructuredGrid::SafeDownCast(object))
        for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
            int type = grid->GetCellType(c);
            lineCells += type == VTK_LINE || type == VTK_POLY_LINE;
        }
    return lineCells;
}

bool isRadiusArray(vtkDataArray* array) {
    if (array->GetNumberOfComponents() != 1 || !array->GetName()) return false;
    std::string name = array->GetName();
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return name == "radius" || name == "radii";
}

// VTK's convention for colours (vtkScalarsToColors, ParaView's "Map Scalars" off): unsigned
// char RGB or RGBA point data.
bool isColorArray(vtkDataArray* array) {
    const int k = array->GetNumberOfComponents();
    return array->GetDataType() == VTK_UNSIGNED_CHAR && (k == 3 || k == 4);
}

// Every point of the data set as a particle (vertex cells or none: a point cloud), with its
// point data; the first 1-component array called radius/radii gives radii, the first unsigned
// char RGB(A) array colours.
ParticleSet extractPoints(const std::string& path, vtkDataSet* data) {
    ParticleSet set;
    vtkPointData* pd = data->GetPointData();
    vtkDataArray* radius = nullptr;
    vtkDataArray* color = nullptr;
    for (int i = 0; pd && i < pd->GetNumberOfArrays(); ++i) {
        vtkDataArray* array = pd->GetArray(i);
        if (!array || array->GetNumberOfTuples() != data->GetNumberOfPoints()) continue;
        if (!radius && isRadiusArray(array))
            radius = array;
        else if (!color && isColorArray(array))
            color = array;
    }
    PointDataColumns columns(data, set.attributes, [&](vtkDataArray* a) { return a == radius || a == color; });
    const vtkIdType n = data->GetNumberOfPoints();
    set.positions.reserve(std::size_t(n));
    for (vtkIdType id = 0; id < n; ++id) {
        double p[3];
        data->GetPoint(id, p);
        const glm::vec3 position{float(p[0]), float(p[1]), float(p[2])};
        if (!std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(position.z))
            throw InputError(path + ": point " + std::to_string(id) + ": non-finite position");
        set.positions.push_back(position);
        columns.append(id, set.attributes);
        if (radius) {
            const double r = radius->GetComponent(id, 0);
            if (!(r > 0.0) || !std::isfinite(r))
                throw InputError(path + ": point " + std::to_string(id) + ": " + radius->GetName() + " " +
                                 std::to_string(r) + " (expected a positive radius)");
            set.radii.push_back(float(r));
        }
        if (color) {
            const int k = color->GetNumberOfComponents();
            glm::vec4 c(1.0f);
            for (int j = 0; j < k; ++j) c[j] = float(color->GetComponent(id, j) / 255.0);
            set.colors.push_back(c);
        }
    }
    if (radius) set.radiiFrom = Provenance::File;
    if (color) set.colorsFrom = Provenance::File;
    set.update();
    return set;
}

LineSet extractLines(const std::string& path, vtkDataObject* object) {
    if (auto* poly = vtkPolyData::SafeDownCast(object)) {
        vtkCellArray* cells = poly->GetLines();
        const vtkIdType lineCells = cells ? cells->GetNumberOfCells() : 0;
        if (lineCells == 0 || !poly->GetPoints()) throwNoPolylines(path, poly, poly->GetNumberOfCells() - lineCells);
        LineSetBuilder builder(path, poly);
        auto it = vtk::TakeSmartPointer(cells->NewIterator());
        for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell()) {
            vtkIdType n;
            const vtkIdType* ids;
            it->GetCurrentCell(n, ids);
            builder.addCell(it->GetCurrentCellId(), n, ids);
        }
        return builder.take();
    }
    if (auto* grid = vtkUnstructuredGrid::SafeDownCast(object)) {
        const vtkIdType cellCount = grid->GetNumberOfCells();
        vtkIdType lineCells = 0;
        for (vtkIdType c = 0; c < cellCount; ++c) {
            int type = grid->GetCellType(c);
            lineCells += type == VTK_LINE || type == VTK_POLY_LINE;
        }
        if (lineCells == 0 || !grid->GetPoints()) throwNoPolylines(path, grid, cellCount - lineCells);
        LineSetBuilder builder(path, grid);
        for (vtkIdType c = 0; c < cellCount; ++c) {
            int type = grid->GetCellType(c);
            if (type != VTK_LINE && type != VTK_POLY_LINE) continue;
            vtkIdType n;
            const vtkIdType* ids;
            grid->GetCellPoints(c, n, ids);
            builder.addCell(c, n, ids);
        }
        return builder.take();
    }
    throw InputError(path + ": not VTK PolyData or an UnstructuredGrid (" +
                     std::string(object ? object->GetClassName() : "no data") + ")");
}

// Runs `reader` and returns its output, turning VTK's complaints into an InputError. `pieces` > 1:
// requests piece `piece` of that many (UpdatePiece), which a parallel XML reader serves with its
// share of the file's pieces.
template <class Reader>
vtkSmartPointer<vtkDataObject> runReader(const std::string& path, Reader* reader, const VtkMessageCapture& capture,
                                         int piece = 0, int pieces = 1) {
    reader->SetFileName(path.c_str());
    if (pieces > 1)
        reader->UpdatePiece(piece, pieces, 0);
    else
        reader->Update();
    if (capture.failed()) throw InputError(path + ": VTK: " + capture.firstError());
    if (reader->GetErrorCode() != 0) throw InputError(path + ": VTK: " + errorCodeText(reader->GetErrorCode()));
    return reader->GetOutputDataObject(0);
}

// The data object of a .vtk / .vtp / .vtu / .pvtp / .pvtu file (isVtkFile); of a .pvtp / .pvtu,
// all its pieces appended in file order, or with `pieces` > 1 the share `piece` of them.
vtkSmartPointer<vtkDataObject> readVtkObject(const std::string& path, int piece = 0, int pieces = 1) {
    const std::string ext = extensionLower(path);
    VtkMessageCapture capture;
    if (ext == ".pvtp") {
        vtkNew<vtkXMLPPolyDataReader> reader;
        return runReader(path, reader.Get(), capture, piece, pieces);
    }
    if (ext == ".pvtu") {
        vtkNew<vtkXMLPUnstructuredGridReader> reader;
        return runReader(path, reader.Get(), capture, piece, pieces);
    }
    TC_CHECK_OP(pieces, ==, 1);
    if (ext == ".vtk") {
        // Generic rather than vtkPolyDataReader: also takes UNSTRUCTURED_GRID files.
        vtkNew<vtkGenericDataObjectReader> reader;
        // By default the legacy reader keeps only the first SCALARS / VECTORS / ... section of
        // each kind (the "active" one) and silently drops the others.
        reader->ReadAllScalarsOn();
        reader->ReadAllVectorsOn();
        reader->ReadAllNormalsOn();
        reader->ReadAllTensorsOn();
        reader->ReadAllColorScalarsOn();
        reader->ReadAllTCoordsOn();
        reader->ReadAllFieldsOn();
        return runReader(path, reader.Get(), capture);
    }
    if (ext == ".vtp") {
        vtkNew<vtkXMLPolyDataReader> reader;
        return runReader(path, reader.Get(), capture);
    }
    TC_CHECK(ext == ".vtu");
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    return runReader(path, reader.Get(), capture);
}

// A file that stores no polylines (an empty tractogram) is a valid, empty line set; one whose
// polylines cleaning removed altogether is an error.
LineSet cleanedLines(const std::string& path, LineSet lines, CleanReport* report,
                     std::vector<std::string> warnings = {}) {
    const bool stored = lines.polylineCount() > 0;
    CleanReport cleaned = cleanLineSet(lines);
    cleaned.warnings = std::move(warnings);
    if (report) *report = cleaned;
    if (stored && lines.polylineCount() == 0)
        throw InputError(path + ": no polylines left after cleaning (" + cleaned.summary() + ")");
    return lines;
}

}  // namespace

LineSet readLineSet(const std::string& path, CleanReport* report) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw InputError(path + ": no such file");
    if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a directory");
    const std::string ext = extensionLower(path);

    LineSet lines;
    std::vector<std::string> warnings;
    if (isNativeLineFormat(ext)) {
        lines = readNativeLineFile(path, &warnings);  // .trk, .tck (+ .tsf), .obj, .tcb: io/line_formats.h
    } else if (isVtkFile(path)) {
        lines = extractLines(path, readVtkObject(path));
    } else {
        throw InputError(path + ": unsupported file extension '" + ext +
                         "' (supported: .vtk, .vtp, .vtu, .trk, .tck, .obj, .tcb)");
    }
    return cleanedLines(path, std::move(lines), report, std::move(warnings));
}

bool isVtkFile(const std::string& path) {
    const std::string ext = extensionLower(path);
    return ext == ".vtk" || ext == ".vtp" || ext == ".vtu" || isPiecedVtkFile(path);
}

bool isPiecedVtkFile(const std::string& path) {
    const std::string ext = extensionLower(path);
    return ext == ".pvtp" || ext == ".pvtu";
}

LineSet readLinePieces(const std::string& path, int share, int shares, CleanReport* report) {
    TC_CHECK(share >= 0 && share < shares);
    TC_CHECK(isPiecedVtkFile(path));
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw InputError(path + ": no such file");
    if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a directory");
    vtkSmartPointer<vtkDataObject> object = readVtkObject(path, share, shares);
    auto* set = vtkDataSet::SafeDownCast(object);
    if (lineCellCount(object) == 0) {
        // More shares than pieces: VTK gives some shares none.
        if (set && set->GetNumberOfPoints() == 0) return LineSet{};
        throw InputError(path + ": share " + std::to_string(share) + " of " + std::to_string(shares) +
                         ": no polylines (" + std::to_string(set ? set->GetNumberOfPoints() : 0) +
                         " points): reading the pieces of a file in parallel takes line data only");
    }
    return cleanedLines(path, extractLines(path, object), report);
}

VtkFileData readVtkFile(const std::string& path, CleanReport* report) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw InputError(path + ": no such file");
    if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a directory");
    vtkSmartPointer<vtkDataObject> object = readVtkObject(path);
    VtkFileData data;
    auto* set = vtkDataSet::SafeDownCast(object);
    if (lineCellCount(object) == 0 && set && set->GetNumberOfPoints() > 0) {
        data.points = extractPoints(path, set);
        data.isPoints = true;
        return data;
    }
    data.lines = cleanedLines(path, extractLines(path, object), report);
    return data;
}

namespace {

vtkNew<vtkPoints> floatPoints(const std::vector<glm::vec3>& positions) {
    vtkNew<vtkPoints> points;
    points->SetDataTypeToFloat();
    points->SetNumberOfPoints(vtkIdType(positions.size()));
    auto* coords = vtkFloatArray::SafeDownCast(points->GetData());
    TC_CHECK(coords != nullptr);
    if (!positions.empty()) std::copy_n(&positions.data()->x, 3 * positions.size(), coords->GetPointer(0));
    return points;
}

void addFloatArray(vtkPolyData* poly, const std::string& name, const std::vector<float>& values) {
    TC_CHECK_OP(vtkIdType(values.size()), ==, poly->GetNumberOfPoints());
    vtkNew<vtkFloatArray> array;
    array->SetName(name.c_str());
    array->SetNumberOfTuples(vtkIdType(values.size()));
    std::copy(values.begin(), values.end(), array->GetPointer(0));
    poly->GetPointData()->AddArray(array);
}

// Raw binary appended data, 64-bit headers (arrays over 4 GiB), through an AtomicFile.
void writePolyData(vtkPolyData* poly, const std::string& path) {
    AtomicFile file(path);
    {
        VtkMessageCapture capture;
        vtkNew<vtkXMLPolyDataWriter> writer;
        writer->SetFileName(file.tempPath().c_str());
        writer->SetInputData(poly);
        writer->SetDataModeToAppended();
        writer->EncodeAppendedDataOff();  // raw binary, not base64
        writer->SetHeaderTypeToUInt64();
        const int ok = writer->Write();
        if (!ok || capture.failed() || writer->GetErrorCode() != 0)
            throw OutputError(path + ": cannot write: " +
                              (capture.failed() ? capture.firstError() : errorCodeText(writer->GetErrorCode())));
    }
    file.commit();
}

}  // namespace

void writeLineSetVtp(const LineSet& lines, const std::string& path) {
    TC_CHECK(!lines.offsets.empty());
    TC_CHECK_OP(std::size_t(lines.offsets.back()), ==, lines.positions.size());

    vtkNew<vtkCellArray> cells;
    cells->AllocateExact(vtkIdType(lines.polylineCount()), vtkIdType(lines.positions.size()));
    std::vector<vtkIdType> ids;
    for (std::size_t p = 0; p < lines.polylineCount(); ++p) {
        ids.resize(lines.offsets[p + 1] - lines.offsets[p]);
        std::iota(ids.begin(), ids.end(), vtkIdType(lines.offsets[p]));
        cells->InsertNextCell(vtkIdType(ids.size()), ids.data());
    }

    vtkNew<vtkPolyData> poly;
    poly->SetPoints(floatPoints(lines.positions));
    poly->SetLines(cells);
    for (const Attribute& a : lines.attributes) addFloatArray(poly, a.name, a.values);
    writePolyData(poly, path);
}

void writeParticleSetVtp(const ParticleSet& particles, const std::string& path) {
    particles.checkConsistent();
    vtkNew<vtkCellArray> cells;  // one vertex cell per particle, as ParaView writes point clouds
    cells->AllocateExact(vtkIdType(particles.size()), vtkIdType(particles.size()));
    for (vtkIdType i = 0; i < vtkIdType(particles.size()); ++i) cells->InsertNextCell(1, &i);

    vtkNew<vtkPolyData> poly;
    poly->SetPoints(floatPoints(particles.positions));
    poly->SetVerts(cells);
    if (!particles.radii.empty()) addFloatArray(poly, "radius", particles.radii);
    if (!particles.colors.empty()) {
        vtkNew<vtkUnsignedCharArray> colors;
        colors->SetName("colors");
        colors->SetNumberOfComponents(4);
        colors->SetNumberOfTuples(vtkIdType(particles.size()));
        for (std::size_t i = 0; i < particles.size(); ++i)
            for (int c = 0; c < 4; ++c)
                colors->SetValue(
                    vtkIdType(4 * i + c),
                    static_cast<unsigned char>(std::lround(std::clamp(particles.colors[i][c], 0.0f, 1.0f) * 255.0f)));
        poly->GetPointData()->AddArray(colors);
    }
    for (const Attribute& a : particles.attributes) addFloatArray(poly, a.name, a.values);
    writePolyData(poly, path);
}

}  // namespace tc
