// A minimal PNG decoder for the browser screenshots (8-bit RGB or RGBA, not interlaced): enough
// to compare pictures without another npm package.
import { inflateSync } from 'node:zlib';

/// Returns { width, height, data } with data RGBA bytes.
export function decodePng(buffer) {
  const signature = '89504e470d0a1a0a';
  if (buffer.subarray(0, 8).toString('hex') !== signature) throw new Error('not a PNG');
  let offset = 8, width = 0, height = 0, colorType = 0;
  const idat = [];
  while (offset < buffer.length) {
    const length = buffer.readUInt32BE(offset);
    const type = buffer.toString('latin1', offset + 4, offset + 8);
    const body = buffer.subarray(offset + 8, offset + 8 + length);
    if (type === 'IHDR') {
      width = body.readUInt32BE(0);
      height = body.readUInt32BE(4);
      colorType = body[9];
      if (body[8] !== 8 || (colorType !== 2 && colorType !== 6) || body[12] !== 0)
        throw new Error(`unsupported PNG (depth ${body[8]}, color type ${colorType}, interlace ${body[12]})`);
    } else if (type === 'IDAT') {
      idat.push(body);
    } else if (type === 'IEND') {
      break;
    }
    offset += 12 + length;
  }
  const bpp = colorType === 6 ? 4 : 3, stride = width * bpp;
  const raw = inflateSync(Buffer.concat(idat));
  const pixels = Buffer.alloc(stride * height);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    const line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    const out = pixels.subarray(y * stride, (y + 1) * stride);
    const prev = y > 0 ? pixels.subarray((y - 1) * stride, y * stride) : Buffer.alloc(stride);
    for (let x = 0; x < stride; ++x) {
      const a = x >= bpp ? out[x - bpp] : 0, b = prev[x], c = x >= bpp ? prev[x - bpp] : 0;
      let predictor = 0;
      if (filter === 1) predictor = a;
      else if (filter === 2) predictor = b;
      else if (filter === 3) predictor = (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        predictor = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      out[x] = (line[x] + predictor) & 255;
    }
  }
  const data = Buffer.alloc(width * height * 4);
  for (let i = 0; i < width * height; ++i) {
    data[4 * i] = pixels[bpp * i];
    data[4 * i + 1] = pixels[bpp * i + 1];
    data[4 * i + 2] = pixels[bpp * i + 2];
    data[4 * i + 3] = bpp === 4 ? pixels[bpp * i + 3] : 255;
  }
  return { width, height, data };
}

/// Fraction of pixels farther than `tolerance` (max channel difference) from `rgb`.
export function fractionNot(image, rgb, tolerance = 8) {
  let count = 0;
  for (let i = 0; i < image.width * image.height; ++i) {
    const d = Math.max(Math.abs(image.data[4 * i] - rgb[0]), Math.abs(image.data[4 * i + 1] - rgb[1]), Math.abs(image.data[4 * i + 2] - rgb[2]));
    if (d > tolerance) ++count;
  }
  return count / (image.width * image.height);
}

/// Fraction of pixels that differ by more than `tolerance` between two same-sized images.
export function fractionChanged(a, b, tolerance = 24) {
  if (a.width !== b.width || a.height !== b.height) return 1;
  let count = 0;
  for (let i = 0; i < a.width * a.height; ++i) {
    let d = 0;
    for (let c = 0; c < 3; ++c) d = Math.max(d, Math.abs(a.data[4 * i + c] - b.data[4 * i + c]));
    if (d > tolerance) ++count;
  }
  return count / (a.width * a.height);
}
