//! Scene loaders: glTF 2.0 (`.gltf`, `.glb`), OBJ + MTL and PLY.
