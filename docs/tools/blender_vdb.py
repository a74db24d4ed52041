# Renders a volume exported by `xylem export -o wood.vdb` in Blender, headless, as proof that
# Blender reads it: the grid `color` (linear RGB) is the emission of a dense, absorbing
# volume, so the cube shows the wood's colour just below its faces, unlit.
#   blender -b --python docs/tools/blender_vdb.py -- wood.vdb out.png
import math
import sys

import bpy

vdb_path, png_path = sys.argv[sys.argv.index("--") + 1 :][:2]
bpy.ops.wm.read_factory_settings(use_empty=True)
volume = bpy.data.volumes.new("wood")
volume.filepath = vdb_path
volume.grids.load()
print("grids:", [(g.name, g.data_type) for g in volume.grids])
obj = bpy.data.objects.new("wood", volume)
bpy.context.scene.collection.objects.link(obj)
# xylem's cube is y-up (the pith along y); Blender is z-up.
obj.rotation_euler = (math.pi / 2, 0.0, 0.0)

mat = bpy.data.materials.new("wood")
mat.use_nodes = True
nodes = mat.node_tree.nodes
nodes.clear()
out = nodes.new("ShaderNodeOutputMaterial")
colour = nodes.new("ShaderNodeAttribute")
colour.attribute_name = "color"
emission = nodes.new("ShaderNodeEmission")
absorption = nodes.new("ShaderNodeVolumeAbsorption")
both = nodes.new("ShaderNodeAddShader")
links = mat.node_tree.links
links.new(colour.outputs["Color"], emission.inputs["Color"])
# Emitted radiance per unit length / absorption per unit length: equal strength and density
# give the grid's colour at the faces (the volume is opaque a few voxels deep).
emission.inputs["Strength"].default_value = 200.0
absorption.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
# Blender pads the volume's bounds beyond the grid, where the colour reads 0: absorb only
# inside the grid (non-zero colour), or the padding becomes a black shell.
length = nodes.new("ShaderNodeVectorMath")
length.operation = "LENGTH"
inside = nodes.new("ShaderNodeMath")
inside.operation = "GREATER_THAN"
inside.inputs[1].default_value = 1e-6
density = nodes.new("ShaderNodeMath")
density.operation = "MULTIPLY"
density.inputs[1].default_value = 200.0
links.new(colour.outputs["Vector"], length.inputs[0])
links.new(length.outputs["Value"], inside.inputs[0])
links.new(inside.outputs["Value"], density.inputs[0])
links.new(density.outputs["Value"], absorption.inputs["Density"])
links.new(emission.outputs["Emission"], both.inputs[0])
links.new(absorption.outputs["Volume"], both.inputs[1])
links.new(both.outputs["Shader"], out.inputs["Volume"])
obj.data.materials.append(mat)

scene = bpy.context.scene
cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(cam)
# xylem render's corner view (eye (2.1, 1.75, 2.75), y-up) in Blender's z-up frame.
cam.location = (2.1, -2.75, 1.75)
direction = -cam.location
cam.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
cam.data.angle = math.radians(30.0)
scene.camera = cam
sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
sun.data.energy = 4.0
sun.rotation_euler = (0.6, 0.2, 0.5)
scene.collection.objects.link(sun)
world = bpy.data.worlds.new("world")
world.color = (0.35, 0.35, 0.35)
scene.world = world
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = 32
scene.cycles.use_denoising = False
scene.render.resolution_x = scene.render.resolution_y = 400
scene.view_settings.view_transform = "Standard"  # plain sRGB, as xylem writes PNGs
scene.render.filepath = png_path
bpy.ops.render.render(write_still=True)
print("rendered", png_path)
