#include "hsr/pixel_data.hpp"

#include "hsr/error.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <limits>

namespace hsr {
namespace {

void check_faces(const Frame& frame, const hsr_scene& scene) {
    if (scene.instance_count > 0 && frame.instance.size() != frame.face.size())
        throw Error("the frame has no instance ids for a scene with instances (a plugin built against ABI 1.0)");
    for (uint32_t face : frame.face)
        if (face != HSR_NO_FACE && face >= scene.triangle_count)
            throw Error("the frame names triangle {} of a scene of {}", face, scene.triangle_count);
}

}  // namespace

std::vector<float> camera_depth(const Frame& frame, const hsr_camera& camera) {
    const glm::dmat4 inverse_projection = glm::inverse(glm::dmat4(glm::make_mat4(camera.projection)));
    std::vector<float> distance(frame.depth.size(), std::numeric_limits<float>::infinity());
    for (uint32_t y = 0; y < frame.height; ++y) {
        const double y_ndc = 1.0 - 2.0 * (y + 0.5) / frame.height;
        for (uint32_t x = 0; x < frame.width; ++x) {
            const size_t i = size_t(y) * frame.width + x;
            if (frame.face[i] == HSR_NO_FACE) continue;
            const double x_ndc = 2.0 * (x + 0.5) / frame.width - 1.0;
            const glm::dvec4 view = inverse_projection * glm::dvec4(x_ndc, y_ndc, 2.0 * frame.depth[i] - 1.0, 1.0);
            distance[i] = float(-view.z / view.w);
        }
    }
    return distance;
}

std::vector<int32_t> pixel_ids(const Frame& frame, const hsr_scene& scene) {
    check_faces(frame, scene);
    // Objects are concatenated (abi.h): an object's first triangle is where its run begins.
    std::vector<uint32_t> first_triangle(scene.object_count, 0);
    for (uint32_t t = scene.triangle_count; t-- > 0;)
        if (scene.face_object[t] < scene.object_count) first_triangle[scene.face_object[t]] = t;
    const bool instanced = !frame.instance.empty();
    std::vector<int32_t> ids(3 * frame.face.size(), -1);
    for (size_t i = 0; i < frame.face.size(); ++i) {
        const uint32_t face = frame.face[i];
        if (face == HSR_NO_FACE) continue;
        const uint32_t object = scene.face_object[face];
        ids[3 * i] = int32_t(object);
        ids[3 * i + 1] = int32_t(face - first_triangle[object]);
        ids[3 * i + 2] = instanced ? int32_t(frame.instance[i]) : 0;
    }
    return ids;
}

std::vector<float> camera_normals(const Frame& frame, const hsr_scene& scene, const hsr_camera& camera) {
    check_faces(frame, scene);
    const glm::mat3 view_rotation(glm::make_mat4(camera.view));  // a rigid view: its upper 3x3 turns
    std::vector<glm::mat3> instance_rotation(scene.instance_count);
    for (uint32_t k = 0; k < scene.instance_count; ++k)
        instance_rotation[k] = view_rotation * glm::make_mat3(HSR_ELEMENT(hsr_instance, scene.instances, k)->rotation);
    const bool instanced = !frame.instance.empty() && scene.instance_count > 0;
    std::vector<float> normals(3 * frame.face.size(), 0.0f);
    for (size_t i = 0; i < frame.face.size(); ++i) {
        const uint32_t face = frame.face[i];
        if (face == HSR_NO_FACE) continue;
        const glm::vec3 n = glm::make_vec3(scene.face_normals + 3 * size_t(face));
        const glm::vec3 turned = glm::normalize(
            (instanced && frame.instance[i] < scene.instance_count ? instance_rotation[frame.instance[i]]
                                                                   : view_rotation) * n);
        for (int c = 0; c < 3; ++c) normals[3 * i + c] = turned[c];
    }
    return normals;
}

}  // namespace hsr
