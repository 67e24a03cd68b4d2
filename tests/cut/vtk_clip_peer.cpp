// The peer `kerf cut` is measured against (bench_cut_setup --peer): a small VTK program that
// does what `kerf cut` does with one plane, the same way (a process: load, cut, write). It reads
// a binary STL, clips it by the plane with vtkClipClosedSurface once per side (each half closed
// by its cap) and writes each half as a binary STL. VTK clips every bone the plane crosses;
// `kerf cut --seed` only the seeded one (less work for Kerf: say so next to any figure).
//
//   vtk_clip_peer IN.stl px py pz nx ny nz OUT_PREFIX      # writes OUT_PREFIX_0.stl, _1.stl
#include <vtkClipClosedSurface.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkPlaneCollection.h>
#include <vtkSTLReader.h>
#include <vtkSTLWriter.h>

#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
    if (argc != 9) {
        std::fprintf(stderr, "usage: vtk_clip_peer IN.stl px py pz nx ny nz OUT_PREFIX\n");
        return 2;
    }
    double v[6];
    for (int i = 0; i < 6; ++i) v[i] = std::strtod(argv[2 + i], nullptr);
    vtkNew<vtkSTLReader> reader;
    reader->SetFileName(argv[1]);
    reader->Update();
    if (reader->GetOutput()->GetNumberOfCells() == 0) {
        std::fprintf(stderr, "vtk_clip_peer: %s: no triangles\n", argv[1]);
        return 1;
    }
    for (int side = 0; side < 2; ++side) {
        const double s = side == 0 ? 1.0 : -1.0;
        vtkNew<vtkPlane> plane;
        plane->SetOrigin(v[0], v[1], v[2]);
        plane->SetNormal(s * v[3], s * v[4], s * v[5]);
        vtkNew<vtkPlaneCollection> planes;
        planes->AddItem(plane);
        vtkNew<vtkClipClosedSurface> clip;
        clip->SetInputConnection(reader->GetOutputPort());
        clip->SetClippingPlanes(planes);
        vtkNew<vtkSTLWriter> writer;
        writer->SetInputConnection(clip->GetOutputPort());
        writer->SetFileTypeToBinary();
        const std::string out = std::string(argv[8]) + "_" + std::to_string(side) + ".stl";
        writer->SetFileName(out.c_str());
        if (writer->Write() != 1) return 1;
    }
    return 0;
}
