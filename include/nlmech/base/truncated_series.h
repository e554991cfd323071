#pragma once
// Small scalar types for Taylor-mode arithmetic without heap allocation:
//  - TruncatedSeries: a power series sum_k c_k a^k truncated at a runtime degree <= Capacity-1,
//    with +, -, *, / and pow(series, double) by the usual recurrences (O(k^2) per product);
//  - ForwardGradient<T, N>: forward-mode derivatives of N inputs over any value type T.
// ForwardGradient<TruncatedSeries, 9> over an energy density W(F) gives the Taylor series of the
// first Piola stress dW/dF along a path F(a), which is what the ANM needs, at a fraction of the cost
// of the allocating Sacado::Tay::Taylor (kept as the generic path and as the cross-check).

#include <algorithm>
#include <array>
#include <cmath>

namespace nlmech
{
  template <int Capacity = 32>
  class TruncatedSeries
  {
  public:
    static constexpr int capacity = Capacity;

    TruncatedSeries(double value = 0.0)
        : d(0)
    {
      c[0] = value;
    }
    /// A series of the given degree with all coefficients zero.
    static TruncatedSeries zero(int degree)
    {
      TruncatedSeries s;
      s.d = degree;
      std::fill(s.c.begin(), s.c.begin() + degree + 1, 0.0);
      return s;
    }

    int     degree() const { return d; }
    double  operator[](int k) const { return k <= d ? c[k] : 0.0; }
    double &coefficient(int k) { return c[k]; }

    TruncatedSeries &operator+=(const TruncatedSeries &b)
    {
      raise_degree(b.d);
      for (int k = 0; k <= b.d; ++k)
        c[k] += b.c[k];
      return *this;
    }
    TruncatedSeries &operator-=(const TruncatedSeries &b)
    {
      raise_degree(b.d);
      for (int k = 0; k <= b.d; ++k)
        c[k] -= b.c[k];
      return *this;
    }
    TruncatedSeries &operator*=(double s)
    {
      for (int k = 0; k <= d; ++k)
        c[k] *= s;
      return *this;
    }
    TruncatedSeries operator-() const
    {
      TruncatedSeries r = *this;
      r *= -1.0;
      return r;
    }

    friend TruncatedSeries operator+(TruncatedSeries a, const TruncatedSeries &b) { return a += b; }
    friend TruncatedSeries operator-(TruncatedSeries a, const TruncatedSeries &b) { return a -= b; }
    friend TruncatedSeries operator*(const TruncatedSeries &a, const TruncatedSeries &b)
    {
      if (a.d == 0)
        return b * a.c[0];
      if (b.d == 0)
        return a * b.c[0];
      TruncatedSeries r;
      r.d = std::max(a.d, b.d);
      for (int k = 0; k <= r.d; ++k)
        {
          double sum = 0;
          for (int j = std::max(0, k - b.d); j <= std::min(k, a.d); ++j)
            sum += a.c[j] * b.c[k - j];
          r.c[k] = sum;
        }
      return r;
    }
    friend TruncatedSeries operator*(TruncatedSeries a, double s) { return a *= s; }
    friend TruncatedSeries operator*(double s, TruncatedSeries a) { return a *= s; }
    friend TruncatedSeries operator/(const TruncatedSeries &a, const TruncatedSeries &b)
    {
      // q = a / b: q_k = (a_k - sum_{j=1}^k b_j q_{k-j}) / b_0
      TruncatedSeries q;
      q.d = std::max(a.d, b.d);
      for (int k = 0; k <= q.d; ++k)
        {
          double sum = a[k];
          for (int j = 1; j <= std::min(k, b.d); ++j)
            sum -= b.c[j] * q.c[k - j];
          q.c[k] = sum / b.c[0];
        }
      return q;
    }
    friend TruncatedSeries operator/(TruncatedSeries a, double s) { return a *= (1.0 / s); }
    friend TruncatedSeries operator/(double s, const TruncatedSeries &b) { return TruncatedSeries(s) / b; }

    /// y = a^p: y_k = 1 / (k a_0) sum_{j=1}^k ((p + 1) j - k) a_j y_{k-j}, from a y' = p a' y.
    friend TruncatedSeries pow(const TruncatedSeries &a, double p)
    {
      TruncatedSeries y;
      y.d    = a.d;
      y.c[0] = std::pow(a.c[0], p);
      for (int k = 1; k <= a.d; ++k)
        {
          double sum = 0;
          for (int j = 1; j <= k; ++j)
            sum += ((p + 1) * j - k) * a.c[j] * y.c[k - j];
          y.c[k] = sum / (k * a.c[0]);
        }
      return y;
    }

  private:
    void raise_degree(int degree)
    {
      if (degree > d)
        {
          std::fill(c.begin() + d + 1, c.begin() + degree + 1, 0.0);
          d = degree;
        }
    }

    std::array<double, Capacity> c;
    int                          d;
  };

  template <typename T, int N>
  struct ForwardGradient
  {
    T                v;
    std::array<T, N> dx;

    ForwardGradient(double value = 0.0)
        : v(value)
        , dx{}
    {
      dx.fill(T(0.0));
    }
    ForwardGradient(const T &value, int seed)
        : v(value)
    {
      dx.fill(T(0.0));
      dx[seed] = T(1.0);
    }

    ForwardGradient &operator+=(const ForwardGradient &b)
    {
      v += b.v;
      for (int i = 0; i < N; ++i)
        dx[i] += b.dx[i];
      return *this;
    }
    ForwardGradient &operator-=(const ForwardGradient &b)
    {
      v -= b.v;
      for (int i = 0; i < N; ++i)
        dx[i] -= b.dx[i];
      return *this;
    }
    friend ForwardGradient operator+(ForwardGradient a, const ForwardGradient &b) { return a += b; }
    friend ForwardGradient operator-(ForwardGradient a, const ForwardGradient &b) { return a -= b; }
    friend ForwardGradient operator+(ForwardGradient a, double s)
    {
      a.v += T(s);
      return a;
    }
    friend ForwardGradient operator-(ForwardGradient a, double s)
    {
      a.v -= T(s);
      return a;
    }
    friend ForwardGradient operator*(const ForwardGradient &a, const ForwardGradient &b)
    {
      ForwardGradient r;
      r.v = a.v * b.v;
      for (int i = 0; i < N; ++i)
        r.dx[i] = a.dx[i] * b.v + a.v * b.dx[i];
      return r;
    }
    friend ForwardGradient operator*(ForwardGradient a, double s)
    {
      a.v = a.v * s;
      for (int i = 0; i < N; ++i)
        a.dx[i] = a.dx[i] * s;
      return a;
    }
    friend ForwardGradient operator*(double s, const ForwardGradient &a) { return a * s; }
    friend ForwardGradient pow(const ForwardGradient &a, double p)
    {
      using std::pow;
      ForwardGradient r;
      r.v            = pow(a.v, p);
      const T factor = p * (r.v / a.v); // p a^(p-1)
      for (int i = 0; i < N; ++i)
        r.dx[i] = factor * a.dx[i];
      return r;
    }
  };
} // namespace nlmech
