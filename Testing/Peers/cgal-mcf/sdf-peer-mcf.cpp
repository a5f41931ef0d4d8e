// SPDX-License-Identifier: BSD-3-Clause
//
// sdf-peer-mcf: optional measurement peer. Computes CGAL's mean-curvature-flow
// curve skeleton of a closed triangle mesh so our own skeletons can be compared
// against it. Built separately against CGAL (GPL); never linked into the product
// and not part of CI. This file itself is BSD-3-Clause.
//
// Usage: sdf-peer-mcf INPUT.off OUTPUT.skel
//
// Output (text):
//   # sdf-peer-mcf CGAL <version> mean curvature flow skeleton
//   v x y z   one per skeleton vertex, in vertex order (%.17g)
//   e a b     one per skeleton edge, 0-based vertex indices
//   r d       one per skeleton vertex, same order: mean distance from the
//             skeleton vertex to the surface vertices CGAL maps to it (its
//             correspondence); "nan" when CGAL maps no surface vertex to it

// Keep the solver single-threaded even if Eigen were built with OpenMP.
#ifndef EIGEN_DONT_PARALLELIZE
#define EIGEN_DONT_PARALLELIZE
#endif

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/IO/OFF.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/Mean_curvature_flow_skeletonization.h>
#include <CGAL/version.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace
{
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Skeletonizer = CGAL::Mean_curvature_flow_skeletonization<Mesh>;
using Skeleton = Skeletonizer::Skeleton;
namespace PMP = CGAL::Polygon_mesh_processing;

int fail(const std::string& message)
{
  std::fprintf(stderr, "sdf-peer-mcf: %s\n", message.c_str());
  return 1;
}

// Reads an OFF file into a closed, triangulated 2-manifold Surface_mesh.
// Returns an empty string on success, otherwise a one-line reason.
std::string read_closed_triangle_mesh(const std::string& path, Mesh& mesh)
{
  // Open the stream ourselves: CGAL's file-name overload prints its own
  // message to stderr for a missing file, and we want exactly one line.
  std::ifstream in(path);
  if (!in)
  {
    return "cannot open '" + path + "'";
  }
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  if (!CGAL::IO::read_OFF(in, points, polygons) || points.empty() || polygons.empty())
  {
    return "cannot read '" + path + "' as an OFF mesh";
  }
  for (const auto& polygon : polygons)
  {
    for (std::size_t id : polygon)
    {
      if (id >= points.size())
      {
        return "'" + path + "': face refers to a vertex index out of range";
      }
    }
  }
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons))
  {
    return "'" + path +
      "' is not a consistently oriented 2-manifold polygon mesh (degenerate face, "
      "non-manifold edge or vertex, or inconsistent orientation)";
  }
  // Vertices are created in file order, so mesh vertex i is OFF vertex i.
  PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);

  if (!CGAL::is_triangle_mesh(mesh))
  {
    if (!PMP::triangulate_faces(mesh) || !CGAL::is_triangle_mesh(mesh))
    {
      return "'" + path + "' has non-triangular faces that could not be triangulated";
    }
  }
  if (!CGAL::is_closed(mesh))
  {
    return "'" + path + "' is not closed (it has boundary edges); MCF needs a closed triangle mesh";
  }
  if (!mesh.is_valid(false))
  {
    return "'" + path + "' produced an invalid halfedge structure";
  }
  return std::string();
}
} // namespace

int main(int argc, char** argv)
{
  if (argc != 3)
  {
    std::fprintf(stderr, "usage: sdf-peer-mcf INPUT.off OUTPUT.skel\n");
    return 1;
  }
  const std::string inputPath = argv[1];
  const std::string outputPath = argv[2];

  try
  {
    Mesh mesh;
    const std::string problem = read_closed_triangle_mesh(inputPath, mesh);
    if (!problem.empty())
    {
      return fail(problem);
    }

    // Skeletonization with CGAL's default parameters; only this part is timed.
    Skeleton skeleton;
    const auto start = std::chrono::steady_clock::now();
    {
      Skeletonizer mcfs(mesh);
      mcfs(skeleton); // contract_until_convergence() + convert_to_skeleton()
    }
    const auto stop = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(stop - start).count();

    std::FILE* out = std::fopen(outputPath.c_str(), "w");
    if (out == nullptr)
    {
      return fail("cannot open '" + outputPath + "' for writing");
    }
    std::fprintf(out, "# sdf-peer-mcf CGAL %s mean curvature flow skeleton\n", CGAL_STR(CGAL_VERSION));

    // With vecS storage, skeleton vertex descriptors are 0..V-1 in order.
    const std::size_t nv = boost::num_vertices(skeleton);
    const std::size_t ne = boost::num_edges(skeleton);
    for (std::size_t v = 0; v < nv; ++v)
    {
      const Point& p = skeleton[v].point;
      std::fprintf(out, "v %.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    }
    for (auto e : CGAL::make_range(boost::edges(skeleton)))
    {
      std::fprintf(out, "e %zu %zu\n", static_cast<std::size_t>(boost::source(e, skeleton)),
        static_cast<std::size_t>(boost::target(e, skeleton)));
    }
    for (std::size_t v = 0; v < nv; ++v)
    {
      const Point& p = skeleton[v].point;
      const auto& corr = skeleton[v].vertices;
      double radius = std::numeric_limits<double>::quiet_NaN();
      if (!corr.empty())
      {
        double sum = 0.0;
        for (auto sv : corr)
        {
          sum += std::sqrt(CGAL::squared_distance(p, mesh.point(sv)));
        }
        radius = sum / static_cast<double>(corr.size());
      }
      std::fprintf(out, "r %.17g\n", radius);
    }
    const bool writeFailed = std::ferror(out) != 0;
    if (std::fclose(out) != 0 || writeFailed)
    {
      return fail("error while writing '" + outputPath + "'");
    }

    std::printf("sdf-peer-mcf: %zu surface faces, %zu skeleton vertices, %zu edges, %.3f s\n",
      static_cast<std::size_t>(mesh.number_of_faces()), nv, ne, seconds);
    return 0;
  }
  catch (const std::exception& error)
  {
    return fail(std::string("CGAL failed: ") + error.what());
  }
  catch (...)
  {
    return fail("CGAL failed with an unknown exception");
  }
}
