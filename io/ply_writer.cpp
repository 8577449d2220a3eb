// io/ply_writer.cpp — save_ply (model_loader.hpp): a mesh as a binary PLY
// file, through assimp's exporter.
#include "model_loader.hpp"

#include "model_math.hpp"

#include <assimp/Exporter.hpp>
#include <assimp/scene.h>

#include <memory>
#include <string>

namespace octray {

using namespace model_math;

void save_ply(const MeshData& mesh, const std::string& path) {
    if (mesh.indices.empty() || mesh.indices.size() % 3 != 0)
        throw ModelError("cannot write " + path + ": no triangles, or an index count that is not a multiple of 3");
    if (mesh.vertices.size() > 0x7FFFFFFFu) throw ModelError("cannot write " + path + ": too many vertices");

    auto scene = std::make_unique<aiScene>();
    scene->mRootNode = new aiNode("root");
    scene->mRootNode->mNumMeshes = 1;
    scene->mRootNode->mMeshes = new unsigned[1]{0};
    scene->mNumMaterials = 1;
    scene->mMaterials = new aiMaterial*[1]{new aiMaterial};
    scene->mNumMeshes = 1;
    scene->mMeshes = new aiMesh*[1]{new aiMesh};

    aiMesh& m = *scene->mMeshes[0];
    m.mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    m.mMaterialIndex = 0;
    m.mNumVertices = static_cast<unsigned>(mesh.vertices.size());
    m.mVertices = new aiVector3D[m.mNumVertices];
    for (unsigned v = 0; v < m.mNumVertices; ++v) {
        const Vec3d& p = mesh.vertices[v];
        m.mVertices[v] = aiVector3D(static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
        if (!finite3({double(m.mVertices[v].x), double(m.mVertices[v].y), double(m.mVertices[v].z)}))
            throw ModelError("cannot write " + path + ": vertex " + std::to_string(v) + " " + vec_str(p) +
                             " does not fit in float");
    }
    m.mNumFaces = static_cast<unsigned>(mesh.indices.size() / 3);
    m.mFaces = new aiFace[m.mNumFaces];
    for (unsigned f = 0; f < m.mNumFaces; ++f) {
        aiFace& face = m.mFaces[f];
        face.mNumIndices = 3;
        face.mIndices = new unsigned[3];
        for (unsigned k = 0; k < 3; ++k) {
            const std::uint32_t i = mesh.indices[3 * std::size_t(f) + k];
            if (i >= m.mNumVertices)
                throw ModelError("cannot write " + path + ": index " + std::to_string(i) + " out of range (" +
                                 std::to_string(m.mNumVertices) + " vertices)");
            face.mIndices[k] = i;
        }
    }

    Assimp::Exporter exporter;
    if (exporter.Export(scene.get(), "plyb", path) != aiReturn_SUCCESS)
        throw ModelError("cannot write " + path + ": " + exporter.GetErrorString());
}

}  // namespace octray
