# Outside oracle: Blender's Cycles (Debian `blender`, GPL; run as a separate program, never linked,
# never needed by ctest) renders a glTF file headless, for the path tracer's efficiency comparison
# (scripts/efficiency_cornell.sh, README "Reference efficiency").
#
#   blender -b --factory-startup --python scripts/oracle_cycles.py -- render IN.gltf OUT.exr \
#       --spp N [--seed S] [--size WxH] [--threads T] [--lambert]
#   blender -b --factory-startup --python scripts/oracle_cycles.py -- error REF_A.exr REF_B.exr TEST.exr...
#
# render: unbiased settings — no clamping, no glossy blur, no denoising, no adaptive sampling,
# 1024 bounces of every kind with Cycles' own Russian roulette, a box pixel filter of 1 pixel (as
# prw), a black world; --lambert replaces every Principled BSDF by a Diffuse BSDF of its base colour
# (the Cornell box glTF says specular 0, which Principled v1 of Blender 3.4 cannot express) and keeps
# its emission.  Prints "cycles: N spp ... CPU-s X" (process CPU time of the render call; Cycles'
# scene sync and BVH build included) and writes a float EXR of the linear radiance.
# error: REF = (REF_A + REF_B) / 2 (two seeds); its own variance is MSE(REF_A, REF_B) / 4; for each
# TEST prints the image mean, MSE against REF and MSE - REF variance, all over pixels and RGB.
import sys
import time

import bpy
import numpy

if not hasattr(numpy, 'bool'):  # Debian's numpy 1.24 dropped the alias Blender 3.4's glTF importer uses
    numpy.bool = bool


def args_after_dashes():
    return sys.argv[sys.argv.index('--') + 1:] if '--' in sys.argv else []


def lambert(materials):
    for m in materials:
        if not m.use_nodes:
            continue
        nt = m.node_tree
        for n in list(nt.nodes):
            if n.type != 'BSDF_PRINCIPLED':
                continue
            col = n.inputs['Base Color'].default_value[:]
            emis = n.inputs['Emission'].default_value[:]
            strength = n.inputs['Emission Strength'].default_value
            dsts = [l.to_node for l in n.outputs['BSDF'].links]
            d = nt.nodes.new('ShaderNodeBsdfDiffuse')
            d.inputs['Color'].default_value = col
            shader = d.outputs[0]
            if strength > 0 and max(emis[:3]) > 0:
                e = nt.nodes.new('ShaderNodeEmission')
                e.inputs['Color'].default_value = emis
                e.inputs['Strength'].default_value = strength
                add = nt.nodes.new('ShaderNodeAddShader')
                nt.links.new(d.outputs[0], add.inputs[0])
                nt.links.new(e.outputs[0], add.inputs[1])
                shader = add.outputs[0]
            for dst in dsts:
                nt.links.new(shader, dst.inputs['Surface'])
            nt.nodes.remove(n)


def render(a):
    src, out = a[0], a[1]
    opts = {'--spp': '16', '--seed': '1', '--size': '256x256', '--threads': '1'}
    flags = set()
    i = 2
    while i < len(a):
        if a[i] == '--lambert':
            flags.add(a[i])
            i += 1
        elif a[i] in opts and i + 1 < len(a):
            opts[a[i]] = a[i + 1]
            i += 2
        else:
            sys.exit('oracle_cycles: unknown argument %s' % a[i])
    w, h = (int(x) for x in opts['--size'].split('x'))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=src)
    sc = bpy.context.scene
    cams = [o for o in sc.objects if o.type == 'CAMERA']
    if not cams:
        sys.exit('oracle_cycles: %s has no camera' % src)
    sc.camera = cams[0]
    if '--lambert' in flags:
        lambert(bpy.data.materials)
    world = bpy.data.worlds.new('black')
    world.use_nodes = True
    world.node_tree.nodes['Background'].inputs['Strength'].default_value = 0
    sc.world = world
    sc.render.engine = 'CYCLES'
    c = sc.cycles
    c.device = 'CPU'
    c.samples = int(opts['--spp'])
    c.seed = int(opts['--seed'])
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = 1024
    c.sample_clamp_direct = c.sample_clamp_indirect = 0
    c.blur_glossy = 0
    c.pixel_filter_type = 'BOX'
    c.filter_width = 1.0
    sc.render.threads_mode = 'FIXED'
    sc.render.threads = int(opts['--threads'])
    sc.render.resolution_x, sc.render.resolution_y = w, h
    sc.render.resolution_percentage = 100
    st = sc.render.image_settings
    st.file_format, st.color_depth, st.exr_codec = 'OPEN_EXR', '32', 'ZIP'
    sc.view_settings.view_transform = 'Standard'
    sc.render.filepath = out
    t0, w0 = time.process_time(), time.time()
    bpy.ops.render.render(write_still=True)
    cpu, wall = time.process_time() - t0, time.time() - w0
    print('cycles: %s spp, %dx%d, seed %s, %s threads, sampling pattern %s, CPU-s %.3f, wall %.3f s, wrote %s'
          % (opts['--spp'], w, h, opts['--seed'], opts['--threads'], c.sampling_pattern, cpu, wall, out))


def load(path):
    im = bpy.data.images.load(path)
    w, h = im.size
    x = numpy.array(im.pixels[:], dtype=numpy.float64).reshape(h, w, 4)[::-1, :, :3]
    bpy.data.images.remove(im)
    return x


def error(a):
    ra, rb = load(a[0]), load(a[1])
    ref = 0.5 * (ra + rb)
    rvar = ((ra - rb) ** 2).mean() / 4
    print('cycles-error: REF (%s + %s) / 2: mean %.6g, its own variance %.6g' % (a[0], a[1], ref.mean(), rvar))
    for p in a[2:]:
        x = load(p)
        if x.shape != ref.shape:
            sys.exit('oracle_cycles: %s is %s, the reference %s' % (p, x.shape, ref.shape))
        mse = ((x - ref) ** 2).mean()
        print('cycles-error: %s: mean %.6g, MSE %.6g, MSE - variance %.6g' % (p, x.mean(), mse, mse - rvar))


a = args_after_dashes()
if not a or a[0] not in ('render', 'error'):
    sys.exit('usage: blender -b --factory-startup --python oracle_cycles.py -- render|error ...')
render(a[1:]) if a[0] == 'render' else error(a[1:])
