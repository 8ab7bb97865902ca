# The numbers of tests/scene/loader_test.cpp's TexturesReadAsNumbersFollowMitsubasEval1: Mitsuba 3's textures read
# as a colour (eval) and as a number (eval_1, what its BSDFs call for a roughness, a blend's weight or an opacity).
# 3.9.1 printed: checkerboard eval 0.05 / eval_1 0.3 at the same halves and the reverse at different halves; an
# rgb (0.2, 0.5, 0.9) as a number 0.53333336 (the channel mean); a bitmap of it 0.46506631 (its luminance).
# Run: python3 tests/scene/mitsuba_textures.py  (pip `mitsuba`)
import mitsuba as mi
import numpy as np

mi.set_variant('scalar_rgb')
si = mi.SurfaceInteraction3f()
checker = mi.load_dict({'type': 'checkerboard', 'color0': 0.05, 'color1': 0.3,
                        'to_uv': mi.ScalarTransform4f().scale([2, 2, 1])})
for uv in [(0.1, 0.1), (0.3, 0.1)]:  # to_uv: (0.2, 0.2) the same halves, (0.6, 0.2) different ones
    si.uv = mi.Point2f(*uv)
    print('checkerboard at', uv, 'eval', checker.eval(si)[0], 'eval_1', checker.eval_1(si))
rgb = mi.load_dict({'type': 'srgb', 'color': [0.2, 0.5, 0.9]})
print('rgb eval_1', rgb.eval_1(si))
texels = np.tile(np.array([0.2, 0.5, 0.9], dtype=np.float32), (2, 2, 1))
print('bitmap eval_1', mi.load_dict({'type': 'bitmap', 'bitmap': mi.Bitmap(texels), 'raw': True}).eval_1(si))
