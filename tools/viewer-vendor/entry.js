// What the viewer (src/hosedrogue/viewer/assets/viewer.js) takes from its libraries, as the
// global HDV: only these names, so esbuild leaves the rest of three.js out of the bundle.
export {
  AmbientLight, BufferAttribute, BufferGeometry, Color, ConeGeometry, CylinderGeometry, DirectionalLight,
  DoubleSide, DynamicDrawUsage, GridHelper, Group, InstancedMesh, Line, LineBasicMaterial, Matrix4, Mesh,
  MeshBasicMaterial, MeshLambertMaterial, PerspectiveCamera, Quaternion, REVISION, Scene, SphereGeometry,
  TorusGeometry, Vector3, WebGLRenderer,
} from "three";
export { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";
export { default as uPlot } from "uplot";
