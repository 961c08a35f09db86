#version 450 core
// Flat-shaded Lambert ("Coloured Model") or a plain line colour for the wireframe ("Polygon").
// `eye` is the viewer's side of each face (for orthographic views, a point far behind the camera).
in vec3 vPosition;
in vec3 vNormal;
out vec4 colour;

uniform vec3 eye;
uniform int wire;
uniform vec3 base;      // the part's colour
uniform vec4 cutPlane;  // points with dot(xyz, p) > w are cut away (the slice's cut; (0,0,0,1): none)

uniform vec3 lightDirection; // towards the light (a headlight follows the camera)

void main() {
    if (dot(cutPlane.xyz, vPosition) > cutPlane.w) discard;
    if (wire != 0) {
        colour = vec4(0.1, 0.95, 0.85, 0.9);
        return;
    }
    vec3 n = normalize(vNormal);
    if (dot(n, eye - vPosition) < 0.0) n = -n; // back faces of open meshes lit from the viewer's side
    float key = max(dot(n, lightDirection), 0.0);
    float fill = 0.5 + 0.5 * n.y; // hemisphere ambient: sky above, ground below
    colour = vec4(base * (0.05 + 0.75 * key + 0.3 * fill), 1.0); // never black
}
