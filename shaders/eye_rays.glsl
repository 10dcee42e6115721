// foveation::eye_ray_direction on the device: the unit direction in tracking
// space through a screen position (pixels, y down) of a view given by the tan
// of its frustum angles (left, right, up, down) and its orientation (unit
// quaternion xyzw). Written in glm's order of operations, so the device
// rounds as the CPU does.
#ifndef FOVEART_EYE_RAYS_GLSL
#define FOVEART_EYE_RAYS_GLSL

vec3 eye_ray_direction(vec4 tan_lrud, vec4 orientation, vec2 size_px, vec2 sample_px) {
  const vec2 s = sample_px / size_px;
  const vec3 v = vec3(tan_lrud.x + s.x * (tan_lrud.y - tan_lrud.x), tan_lrud.z + s.y * (tan_lrud.w - tan_lrud.z), -1.0);
  const vec3 q = orientation.xyz;
  const vec3 uv = vec3(q.y * v.z - v.y * q.z, q.z * v.x - v.z * q.x, q.x * v.y - v.x * q.y);          // glm::cross
  const vec3 uuv = vec3(q.y * uv.z - uv.y * q.z, q.z * uv.x - uv.z * q.x, q.x * uv.y - uv.x * q.y);
  const vec3 d = v + ((uv * orientation.w) + uuv) * 2.0;                                            // glm quat * vec3
  return d * (1.0 / sqrt(dot(d, d)));                                                               // glm::normalize
}

#endif
