// Loads a mesh, bakes a small field, queries the centre and saves the field: the library's facade
// through its installed headers alone.
#include <sdfgen/sdfgen.hpp>

#include <cstdio>

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: consumer MESH OUT.sdf\n");
        return 2;
    }
    try {
        const sdfgen::Model model = sdfgen::Model::load(argv[1]);
        sdfgen::BakeSettings settings;
        settings.res = 16;
        const sdfgen::BakeResult result = model.bake(settings);
        const sdfgen::Field& field = result.field.dense();
        sdfgen::saveField(field, argv[2]);
        const sdfgen::WorldBounds box = model.mesh().worldBounds();
        const glm::dvec3 centre = 0.5 * (box.min + box.max);
        const float inside = model.signedDistance({centre})[0];
        std::printf("%zu triangles, %dx%dx%d samples, sign %s, distance at the centre %g\n", model.mesh().triangleCount(),
                    field.grid.dims.x, field.grid.dims.y, field.grid.dims.z,
                    sdfgen::toString(result.sign), double(inside));
        return 0;
    } catch (const sdfgen::Error& e) {
        std::fprintf(stderr, "consumer: %s\n", e.what());
        return 1;
    }
}
