// The shared object is foveart_layer_impl plus the export rules (exports.map).
