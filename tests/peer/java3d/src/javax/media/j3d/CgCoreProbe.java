/*
 * holo peer harness: the same probe as CgProbe, over Java 3D 1.5.2's *core* copy of the
 * decoder (javax.media.j3d.GeometryDecompressor and GeneralizedStrip, the ones behind the
 * CompressedGeometry scene-graph node), compiled into package javax.media.j3d to reach them.
 * `CgTool decode --core` uses it; selfcheck.sh checks that both copies decode the frozen
 * vectors identically. Creates no scene-graph object.
 */
package javax.media.j3d;

import com.sun.j3d.utils.geometry.compression.CgProbe;
import javax.vecmath.Color4f;
import javax.vecmath.Point3f;
import javax.vecmath.Vector3f;

public final class CgCoreProbe extends GeometryDecompressor {
    private CgProbe.Result result;
    private CgProbe.Segment current;

    /** Decode size bytes of data from start, with a fresh decoder state. */
    public static CgProbe.Result decode(int major, int minor, byte[] data, int start, int size) {
        CgCoreProbe p = new CgCoreProbe();
        if (!p.checkVersion(major, minor)) {
            throw new IllegalArgumentException("compressed geometry version " + major + "." + minor + " not supported");
        }
        p.result = new CgProbe.Result();
        p.decompress(start, size, data);
        p.finish();
        return p.result;
    }

    private void finish() {
        if (current == null) {
            return;
        }
        final CgProbe.Segment s = current;
        if (s.vertices.size() > 0) {
            int[] t = GeneralizedStrip.toTriangles(new GeneralizedStripFlags() {
                public int getFlagCount() {
                    return s.getFlagCount();
                }

                public int getFlag(int i) {
                    return s.getFlag(i);
                }
            }, GeneralizedStripFlags.FRONTFACE_CCW);
            s.triangles = t == null ? new int[0] : t;
        }
        result.vertexCount += s.vertices.size();
        result.triangleCount += s.triangles.length / 3;
        result.segments.add(s);
        current = null;
    }

    void outputVertexFormat(boolean bundlingNorm, boolean bundlingColor, boolean doingAlpha) {
        finish();
        current = new CgProbe.Segment(bundlingNorm, bundlingColor, bundlingColor && doingAlpha);
    }

    void outputVertex(Point3f p, Vector3f n, Color4f c, int flag) {
        if (current == null) {
            current = new CgProbe.Segment(false, false, false);
        }
        CgProbe.Vertex v = new CgProbe.Vertex();
        v.flag = flag;
        v.x = p.x; v.y = p.y; v.z = p.z;
        v.nx = n.x; v.ny = n.y; v.nz = n.z;
        v.r = c.x; v.g = c.y; v.b = c.z; v.a = c.w;
        current.vertices.add(v);
    }

    void outputColor(Color4f color) {
        if (current != null && current.vertices.size() > 0) {
            CgProbe.Segment s = current;
            finish();
            current = new CgProbe.Segment(s.normals, s.colors, s.alpha);
        }
    }

    void outputNormal(Vector3f normal) {
        if (current != null && !current.normals && current.vertices.size() > 0) {
            CgProbe.Segment s = current;
            finish();
            current = new CgProbe.Segment(s.normals, s.colors, s.alpha);
        }
    }
}
