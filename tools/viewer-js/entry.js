// The part of three.js the armanim viewer page uses, as one global: window.THREE.
// Bundled by build.sh (esbuild, minified IIFE); only these classes are kept.
import {
  AmbientLight, BufferAttribute, BufferGeometry, CapsuleGeometry, Color, CylinderGeometry, DirectionalLight,
  DoubleSide, Group, HemisphereLight, Line, LineBasicMaterial, LineSegments, Mesh, MeshBasicMaterial,
  MeshLambertMaterial, MeshPhongMaterial, OrthographicCamera, PCFSoftShadowMap, PlaneGeometry, Quaternion, Scene,
  ShadowMaterial, SphereGeometry, Vector3, WebGLRenderer,
} from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

window.THREE = {
  AmbientLight, BufferAttribute, BufferGeometry, CapsuleGeometry, Color, CylinderGeometry, DirectionalLight,
  DoubleSide, Group, HemisphereLight, Line, LineBasicMaterial, LineSegments, Mesh, MeshBasicMaterial,
  MeshLambertMaterial, MeshPhongMaterial, OrthographicCamera, PCFSoftShadowMap, PlaneGeometry, Quaternion, Scene,
  ShadowMaterial, SphereGeometry, Vector3, WebGLRenderer, OrbitControls,
};
