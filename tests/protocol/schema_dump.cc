// Prints the bounds check's schema table (generated from the .lcm files by
// lcmtypes/lcm_schema.py) in the layout of `lcm-gen -d`, normalised by
// schema_test.sh, which compares the two.

#include <cstdio>
#include <string>

#include "protocol/bounds.h"

int main() {
  using dynapath::protocol::SchemaTypeCount;
  using dynapath::protocol::SchemaTypes;
  namespace schema = dynapath::protocol::schema;
  for (int t = 0; t < SchemaTypeCount(); ++t) {
    const schema::Type& type = SchemaTypes()[t];
    std::printf("struct %s.%s\n", type.package, type.name);
    for (int f = 0; f < type.num_fields; ++f) {
      const schema::Field& field = type.fields[f];
      std::string type_name = field.type_name;
      if (field.kind == schema::Kind::kStruct) {
        const schema::Type& nested = SchemaTypes()[field.struct_type];
        type_name = std::string(nested.package) + "." + nested.name;
      }
      std::printf("%s %s", type_name.c_str(), field.name);
      for (int d = 0; d < field.num_dims; ++d) {
        if (field.dims[d].field >= 0) {
          std::printf(" [ (var) %s ]", type.fields[field.dims[d].field].name);
        } else {
          std::printf(" [ (const) %d ]", field.dims[d].size);
        }
      }
      std::printf("\n");
    }
  }
  return 0;
}
