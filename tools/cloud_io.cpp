#include <meshless_tools/cloud_io.h>

#include <meshless_tools/file_checks.h>

#include <pcl/common/io.h>
#include <pcl/io/obj_io.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/io/vtk_io.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace meshless_tools {

namespace {

/** x, y, z of every point of a blob whose coordinates are float or double
  * (pcl::fromPCLPointCloud2 converts only matching types, and many PLY files store
  * doubles). Returns an empty string or the reason it failed. */
std::string
pointsFromBlob (const pcl::PCLPointCloud2& blob, const std::string& path,
                pcl::PointCloud<pcl::PointXYZ>& cloud)
{
  const pcl::PCLPointField* xyz[3] = {nullptr, nullptr, nullptr};
  for (const auto& field : blob.fields)
    for (int axis = 0; axis < 3; ++axis)
      if (field.name == std::string (1, "xyz"[axis]))
        xyz[axis] = &field;
  for (const auto* field : xyz)
    if (!field || (field->datatype != pcl::PCLPointField::FLOAT32 &&
                   field->datatype != pcl::PCLPointField::FLOAT64))
      return path + ": needs float or double x, y and z properties";
  const std::size_t count = static_cast<std::size_t> (blob.width) * blob.height;
  // The reader's blob is consistent; checked anyway, since the copy trusts it.
  for (const auto* field : xyz)
    if (field->offset + pcl::getFieldSize (field->datatype) > blob.point_step)
      return path + ": a coordinate lies outside its point";
  if (blob.data.size () / std::max<std::size_t> (blob.point_step, 1) < count)
    return path + ": fewer data than points";
  cloud.resize (count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint8_t* point = blob.data.data () + i * blob.point_step;
    for (int axis = 0; axis < 3; ++axis) {
      const std::uint8_t* at = point + xyz[axis]->offset;
      float value;
      if (xyz[axis]->datatype == pcl::PCLPointField::FLOAT32)
        std::memcpy (&value, at, sizeof (float));
      else {
        double wide;
        std::memcpy (&wide, at, sizeof (double));
        value = static_cast<float> (wide);
      }
      cloud[i].data[axis] = value;
    }
  }
  cloud.is_dense = false;
  return "";
}

/** A PCD file, checked first (PCL's reader trusts its header). Float coordinates go
  * through pcl::fromPCLPointCloud2, as pcl::io::loadPCDFile does; doubles are
  * converted. */
std::string
loadPcd (const std::string& path, pcl::PointCloud<pcl::PointXYZ>& cloud)
{
  const std::string cause = checkPcdFile (path);
  if (!cause.empty ())
    return path + ": " + cause;
  pcl::PCLPointCloud2 blob;
  int version = 0;
  if (pcl::PCDReader ().read (path, blob, cloud.sensor_origin_, cloud.sensor_orientation_,
                              version) != 0)
    return path + ": PCL's PCD reader refused the file";
  int float_coordinates = 0;
  for (const auto& field : blob.fields)
    if ((field.name == "x" || field.name == "y" || field.name == "z") &&
        field.datatype == pcl::PCLPointField::FLOAT32)
      ++float_coordinates;
  if (float_coordinates != 3)
    return pointsFromBlob (blob, path, cloud);
  pcl::fromPCLPointCloud2 (blob, cloud);
  return "";
}

/** The next whitespace-separated token as a float. strtof, unlike operator>>, reads
  * the "nan" and "inf" that programs write for invalid points. */
bool
parseFloat (std::istream& in, float& value)
{
  std::string token;
  if (!(in >> token))
    return false;
  char* end = nullptr;
  value = std::strtof (token.c_str (), &end);
  return end == token.c_str () + token.size ();
}

/** x y z per line ('#' comments, blank lines skipped; further columns ignored). */
std::string
loadXyz (const std::string& path, pcl::PointCloud<pcl::PointXYZ>& cloud)
{
  std::ifstream in (path);
  if (!in)
    return "cannot open " + path;
  std::string line;
  std::size_t number = 0;
  while (std::getline (in, line)) {
    ++number;
    if (line.empty () || line[0] == '#')
      continue;
    std::istringstream fields (line);
    pcl::PointXYZ point;
    for (int axis = 0; axis < 3; ++axis)
      if (!parseFloat (fields, point.data[axis]))
        return path + ":" + std::to_string (number) + ": expected three numbers";
    cloud.push_back (point);
  }
  cloud.is_dense = false; // may hold nan/inf written as text
  return "";
}

} // namespace

bool
endsWith (const std::string& s, const std::string& suffix)
{
  return s.size () >= suffix.size () &&
         s.compare (s.size () - suffix.size (), suffix.size (), suffix) == 0;
}

std::string
loadCloud (const std::string& path, pcl::PointCloud<pcl::PointXYZ>& cloud)
{
  // PCL's readers may still throw (out of memory): a cause, not a crash.
  try {
    if (endsWith (path, ".pcd"))
      return loadPcd (path, cloud);
    if (endsWith (path, ".ply")) {
      const std::string cause = checkPlyFile (path);
      if (!cause.empty ())
        return path + ": " + cause;
      pcl::PCLPointCloud2 blob;
      if (pcl::io::loadPLYFile (path, blob) != 0)
        return path + ": PCL's PLY reader refused the file";
      return pointsFromBlob (blob, path, cloud);
    }
    if (endsWith (path, ".xyz"))
      return loadXyz (path, cloud);
  } catch (const std::exception& e) {
    return path + ": " + e.what ();
  }
  return "unknown input format (expected .pcd, .ply or .xyz): " + path;
}

std::string
loadMesh (const std::string& path, pcl::meshless::Points3& vertices,
          pcl::meshless::Triangles& triangles)
{
  if (!endsWith (path, ".ply"))
    return "unknown mesh format (expected .ply): " + path;
  const std::string cause = checkPlyFile (path);
  if (!cause.empty ())
    return path + ": " + cause;
  pcl::PolygonMesh mesh;
  try {
    if (pcl::io::loadPLYFile (path, mesh) != 0)
      return path + ": PCL's PLY reader refused the mesh";
  } catch (const std::exception& e) {
    return path + ": " + e.what ();
  }
  pcl::PointCloud<pcl::PointXYZ> cloud;
  const std::string error = pointsFromBlob (mesh.cloud, path, cloud);
  if (!error.empty ())
    return error;
  vertices = toPoints (cloud);
  triangles.clear ();
  for (const auto& polygon : mesh.polygons)
    for (std::size_t k = 2; k < polygon.vertices.size (); ++k)
      triangles.push_back ({static_cast<pcl::index_t> (polygon.vertices[0]),
                            static_cast<pcl::index_t> (polygon.vertices[k - 1]),
                            static_cast<pcl::index_t> (polygon.vertices[k])});
  if (triangles.empty ())
    return path + " has no faces";
  return "";
}

std::string
saveMesh (const std::string& path, const pcl::PolygonMesh& mesh)
{
  int status = -1;
  if (endsWith (path, ".ply"))
    status = pcl::io::savePLYFileBinary (path, mesh);
  else if (endsWith (path, ".vtk"))
    status = pcl::io::saveVTKFile (path, mesh);
  else if (endsWith (path, ".obj"))
    status = pcl::io::saveOBJFile (path, mesh);
  else
    return "unknown output format (expected .ply, .vtk or .obj): " + path;
  return status == 0 ? "" : "cannot write " + path;
}

pcl::meshless::Points3
toPoints (const pcl::PointCloud<pcl::PointXYZ>& cloud)
{
  pcl::meshless::Points3 points;
  points.reserve (cloud.size ());
  for (const auto& p : cloud)
    points.emplace_back (p.x, p.y, p.z);
  return points;
}

pcl::meshless::Triangles
toTriangles (const pcl::PolygonMesh& mesh)
{
  pcl::meshless::Triangles triangles;
  triangles.reserve (mesh.polygons.size ());
  for (const auto& polygon : mesh.polygons)
    if (polygon.vertices.size () == 3)
      triangles.push_back ({static_cast<pcl::index_t> (polygon.vertices[0]),
                            static_cast<pcl::index_t> (polygon.vertices[1]),
                            static_cast<pcl::index_t> (polygon.vertices[2])});
  return triangles;
}

std::string
format (const char* pattern, double value)
{
  char buffer[64];
  std::snprintf (buffer, sizeof (buffer), pattern, value);
  return buffer;
}

} // namespace meshless_tools
