# Generates the table of tests/scene/principled_test.cpp: Mitsuba 3's own principled BSDF (pip `mitsuba`,
# scalar_rgb; 3.9.1 gave the checked-in numbers) evaluated, f·cos, at fixed direction pairs in the local frame.
# Run: python3 tests/scene/mitsuba_principled.py  (prints JSON: per case, [wo θ,φ], [wi θ,φ], rgb, Mitsuba's pdf)
import mitsuba as mi, math, json, sys
mi.set_variant('scalar_rgb')
def d(t,p):
    t=math.radians(t); p=math.radians(p)
    return [math.sin(t)*math.cos(p), math.sin(t)*math.sin(p), math.cos(t)]
cases = {
 'default': {'type':'principled'},
 'metallic_aniso': {'type':'principled','base_color':{'type':'rgb','value':[0.9,0.6,0.2]},'metallic':0.7,'roughness':0.3,'anisotropic':0.6,'spec_tint':0.4},
 'coat_sheen_flat': {'type':'principled','base_color':{'type':'rgb','value':[0.2,0.5,0.8]},'clearcoat':0.8,'clearcoat_gloss':0.5,'sheen':0.6,'sheen_tint':0.5,'flatness':0.4,'roughness':0.6},
 'glossy_eta': {'type':'principled','base_color':{'type':'rgb','value':[0.3,0.3,0.3]},'roughness':0.2,'eta':1.8,'spec_tint':1.0},
}
cases['spec_trans'] = {'type':'principled','base_color':{'type':'rgb','value':[0.8,0.9,0.6]},'spec_trans':0.7,'roughness':0.3,'eta':1.5,'metallic':0.1,'clearcoat':0.3,'sheen':0.2}
cases['spec_trans_full_specular'] = {'type':'principled','spec_trans':1.0,'roughness':0.5,'specular':0.3}
cases['thin_default'] = {'type':'principledthin'}
cases['thin_full'] = {'type':'principledthin','base_color':{'type':'rgb','value':[0.7,0.4,0.2]},'spec_trans':0.6,'diff_trans':0.8,'roughness':0.4,'eta':1.4,'spec_tint':0.5,'sheen':0.5,'sheen_tint':0.3,'flatness':0.3,'anisotropic':0.4}
pairs=[((30,20),(40,200)),((60,0),(55,180)),((10,90),(70,45)),((75,30),(20,250)),((45,0),(45,180)),((30,20),(160,200)),((50,0),(140,170)),((150,10),(20,190)),((140,0),(135,180)),((170,30),(120,200))]
out={}
for name,c in cases.items():
    b=mi.load_dict(c)
    si=mi.SurfaceInteraction3f(); si.sh_frame=mi.Frame3f([0,0,1]); si.n=[0,0,1]
    rows=[]
    for (o,i) in pairs:
        si.wi=mi.Vector3f(d(*o)); wi=mi.Vector3f(d(*i))
        v=b.eval(mi.BSDFContext(), si, wi)
        p=b.pdf(mi.BSDFContext(), si, wi)
        rows.append([o,i,[float(v[0]),float(v[1]),float(v[2])], float(p)])
    out[name]=rows
json.dump(out, sys.stdout, indent=0)
