// Java 3D 1.5.2 reads a .cg file and decodes every object in it: the peer
// check of the geometry blocks of a HoloFlick (spec/holoflick.md §6.4, §12),
// lifted out with `cargo run --example hflk_to_cg -- MOVIE.hflk OUT.cg`.
//
//   J3D=/usr/share/java/j3dutils.jar:/usr/share/java/j3dcore.jar:/usr/share/java/vecmath.jar
//   javac -cp $J3D -d DIR tests/peer/CgBlocks.java
//   java -Djava.awt.headless=false -cp DIR:$J3D CgBlocks OUT.cg
//
// (headless=false: Java 3D's scene graph refuses to load in headless mode, and
// it needs no display to build a Shape3D.) Prints the file version, then per
// object its header and decoded vertices; exits non-zero if one fails.
import com.sun.j3d.utils.geometry.compression.CompressedGeometryData;
import com.sun.j3d.utils.geometry.compression.CompressedGeometryFile;
import javax.media.j3d.GeometryArray;
import javax.media.j3d.Shape3D;

public class CgBlocks {
    public static void main(String[] args) throws Exception {
        CompressedGeometryFile file = new CompressedGeometryFile(args[0], false);
        System.out.println("version " + file.getMajorVersionNumber() + "." + file.getMinorVersionNumber() + "."
                + file.getMinorMinorVersionNumber() + ", " + file.getObjectCount() + " objects");
        CompressedGeometryData[] objects = file.read();
        for (int k = 0; k < objects.length; k++) {
            CompressedGeometryData.Header h = new CompressedGeometryData.Header();
            objects[k].getCompressedGeometryHeader(h);
            StringBuilder line = new StringBuilder("object " + k + ": " + h.size + " bytes, buffer type "
                    + h.bufferType + ", data present " + h.bufferDataPresent + ":");
            Shape3D[] shapes = objects[k].decompress();
            if (shapes == null || shapes.length == 0) {
                System.out.println(line + " no shapes");
                System.exit(1);
            }
            float[] c = new float[3];
            for (Shape3D shape : shapes) {
                GeometryArray g = (GeometryArray) shape.getGeometry();
                line.append(" ").append(g.getClass().getSimpleName());
                for (int i = 0; i < g.getVertexCount(); i++) {
                    g.getCoordinate(i, c);
                    line.append(" (" + c[0] + ", " + c[1] + ", " + c[2] + ")");
                }
            }
            System.out.println(line);
        }
        file.close();
    }
}
